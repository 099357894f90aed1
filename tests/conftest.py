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
