"""Shared fixtures: the real textures of ../shared/textures, cropped small."""

from pathlib import Path

import numpy as np
import pytest

from texsynth.io import load_image

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def load_texture(name, size=None, *, rgb=True):
    """A real texture from ../shared/textures, optionally cropped to ``size`` (top-left) and without alpha."""
    if not TEXTURES.is_dir():
        pytest.skip(f"real textures folder {TEXTURES} is absent (CI always has it)")
    image = load_image(TEXTURES / name)
    if rgb and image.ndim == 3 and image.shape[-1] == 4:
        image = image[..., :3]
    if size is not None:
        h, w = (size, size) if np.isscalar(size) else size
        image = image[:h, :w]
    return np.ascontiguousarray(image)


@pytest.fixture
def texture():
    return load_texture


def interrupt_writer(args, sig):
    """Run ``python *args``, send it ``sig`` once it prints ``writing``, and return its exit code.

    The waits are guards against a hang, not timing assertions.
    """
    import subprocess
    import sys

    proc = subprocess.Popen([sys.executable, *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        if proc.stdout.readline().strip() != "writing":
            proc.wait(timeout=120)
            pytest.fail(f"the writer did not start: {proc.stderr.read()[-2000:]}")
        proc.send_signal(sig)
        proc.wait(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        proc.stdout.close()
        proc.stderr.close()
    return proc.returncode
