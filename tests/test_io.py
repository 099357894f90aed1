"""Image and frame I/O: round trips, bit depths, atomic and non-overwriting saves."""

import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from conftest import interrupt_writer
from texsynth import data
from texsynth.io import image_bits, load_frames, load_image, save_frames, save_image, to_uint

POSIX = pytest.mark.skipif(os.name != "posix", reason="POSIX permissions and signals")


def test_png_round_trip_is_exact_at_8_bits(tmp_path):
    image = data.load("bread")
    path = save_image(tmp_path / "bread.png", image)
    assert np.array_equal(load_image(path), image)


def test_grey_layout_is_kept(tmp_path):
    grey = data.load("metal")[:32, :40]
    out = load_image(save_image(tmp_path / "g.png", grey))
    assert out.shape == (32, 40)
    single = load_image(save_image(tmp_path / "g1.png", grey[..., None]))
    assert single.shape == (32, 40)  # a 1-channel file is read back as grey


def test_sixteen_bit_png_and_tiff_keep_precision(tmp_path):
    ramp = np.linspace(0, 1, 1000).reshape(20, 50)
    for name, kw in (("r.png", {"bits": 16}), ("r.tif", {})):
        out = load_image(save_image(tmp_path / name, ramp, **kw))
        assert np.abs(out - ramp).max() <= 0.5 / 65535 + 1e-12
    eight = load_image(save_image(tmp_path / "r8.png", ramp))
    assert np.abs(eight - ramp).max() > 1e-3  # 8 bits really quantise


def test_npy_keeps_floats(tmp_path):
    volume = np.random.default_rng(0).random((4, 5, 6))
    path = save_image(tmp_path / "v.npy", volume)
    assert np.array_equal(np.load(path), volume)


def test_save_never_overwrites_by_surprise(tmp_path):
    path = save_image(tmp_path / "a.png", np.zeros((4, 4)))
    before = path.read_bytes()
    with pytest.raises(FileExistsError, match="overwrite=True"):
        save_image(path, np.ones((4, 4)))
    assert path.read_bytes() == before
    save_image(path, np.ones((4, 4)), overwrite=True)
    assert load_image(path).min() == 1.0


def test_failed_save_leaves_nothing_behind(tmp_path):
    with pytest.raises(ValueError, match="suffix"):
        save_image(tmp_path / "a.xyz", np.zeros((4, 4)))
    with pytest.raises(ValueError, match="NaN"):
        save_image(tmp_path / "b.png", np.full((4, 4), np.nan))
    assert list(tmp_path.iterdir()) == []


def test_missing_and_unreadable_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        load_image(tmp_path / "nope.png")
    bad = tmp_path / "bad.png"
    bad.write_text("not an image")
    with pytest.raises(ValueError, match="cannot read"):
        load_image(bad)
    with pytest.raises(FileNotFoundError, match="folder"):
        save_image(tmp_path / "missing" / "a.png", np.zeros((2, 2)))


def test_to_uint_rounds_and_refuses_what_it_would_have_clipped():
    assert to_uint(np.array([0.0, 0.5, 1.0])).tolist() == [0, 128, 255]
    assert to_uint(np.array([1.0]), 16).tolist() == [65535]
    # integer data are scaled like everywhere else, not clipped as if they were floats
    assert to_uint(np.array([0, 200, 255], np.uint8)).tolist() == [0, 200, 255]
    assert to_uint(np.array([0, 200, 255], np.uint8), 16).tolist() == [0, 200 * 257, 65535]
    with pytest.raises(ValueError, match="bits"):
        to_uint(np.zeros(2), 12)
    with pytest.raises(ValueError, match=r"image has values in \[-0.1, 1.2\].*np.clip"):
        to_uint(np.array([-0.1, 0.5, 1.2]))
    with pytest.raises(ValueError, match="divide 0-255 data by 255"):
        to_uint([np.nan, 0.5, 200.0][1:])
    with pytest.raises(ValueError, match="image contains NaN"):
        to_uint([np.nan, 0.5, 200.0])
    with pytest.raises(TypeError, match="image must be an array.*got NoneType"):
        to_uint(None)
    with pytest.raises(TypeError, match="bits"):
        to_uint(np.zeros(2), True)


_TO_UINT_INPUTS = {
    "uint8": lambda rng: rng.integers(0, 256, 1000, dtype=np.uint8),
    "uint16": lambda rng: rng.integers(0, 65536, 1000, dtype=np.uint16),
    "bool": lambda rng: rng.random(1000) < 0.5,
    "float32": lambda rng: rng.random(1000, dtype=np.float32),
    "float64": lambda rng: np.append(rng.random(997), [0.5 / 255, 1.5 / 255, 0.5 / 65535]),  # ties round to even
}


@pytest.mark.parametrize("bits", [8, 16])
@pytest.mark.parametrize("kind", list(_TO_UINT_INPUTS))
def test_to_uint_gives_the_bits_of_the_plain_formula_and_keeps_its_input(kind, bits):
    from texsynth.core._validate import as_float_array

    image = _TO_UINT_INPUTS[kind](np.random.default_rng(0))
    before = image.copy()
    want = np.round(as_float_array(image) * (2**bits - 1)).astype(np.uint8 if bits == 8 else np.uint16)
    got = to_uint(image, bits)
    assert got.dtype == want.dtype and np.array_equal(got, want)
    assert np.array_equal(image, before)  # the caller's array is not scaled in place


def test_to_uint_refuses_what_cannot_fit_before_converting():
    from texsynth.core._validate import memory_limit

    with memory_limit(1e4, "a test's limit"), pytest.raises(
            ValueError, match=r"image=\(100, 100\) needs about .* GiB .* of a test's limit; pass a smaller image"):
        to_uint(np.zeros((100, 100), np.uint8))


@pytest.mark.parametrize("bits", [8, 16])
@pytest.mark.parametrize("kind", list(_TO_UINT_INPUTS))
def test_to_uint_memory_estimate_bounds_its_peak_and_holds_one_scaled_copy(monkeypatch, kind, bits):
    import tracemalloc

    import texsynth.io

    estimates = []
    monkeypatch.setattr(texsynth.io._images, "check_memory", lambda nbytes, *args, **kwargs: estimates.append(nbytes))
    image = np.resize(_TO_UINT_INPUTS[kind](np.random.default_rng(0)), 200_000)
    copy = 4 if kind == "float32" else 8  # bytes of a float value
    tracemalloc.start()
    try:
        out = to_uint(image, bits)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert estimates[-1] + 2**14 >= peak  # (numpy's scalars and views take a few hundred bytes more)
    # uint8 and uint16 are scaled into a second float copy; the arithmetic then works in place
    assert peak < 2 * copy * image.size + out.nbytes


@pytest.mark.parametrize("target", ["anim.gif", "frames"])
def test_frames_round_trip(tmp_path, target):
    base = data.load("bumpy")[:24, :32]
    frames = np.stack([np.roll(base, 3 * t, axis=1) for t in range(5)])
    path = save_frames(tmp_path / target, frames, fps=12)
    back = load_frames(path)
    assert back.shape == (5, 24, 32, 3)
    tolerance = 0.5 / 255 + 1e-9 if target == "frames" else 0.25  # GIF palettes quantise colour
    assert np.abs(back - frames).mean() <= tolerance
    with pytest.raises(FileExistsError):
        save_frames(path, frames)


def test_grey_frames_get_a_channel_axis(tmp_path):
    frames = np.random.default_rng(0).random((3, 8, 8))
    back = load_frames(save_frames(tmp_path / "g", frames))
    assert back.shape == (3, 8, 8, 1)
    assert np.abs(back[..., 0] - frames).max() <= 0.5 / 255 + 1e-9


def test_load_image_refuses_missing_frames_folder(tmp_path):
    with pytest.raises(ValueError, match="no image files"):
        load_frames(tmp_path)


def test_grey_gif_round_trip_keeps_one_channel(tmp_path):
    frames = np.stack([np.roll(np.linspace(0, 1, 64).reshape(8, 8), t, axis=1) for t in range(3)])
    back = load_frames(save_frames(tmp_path / "g.gif", frames))
    assert back.shape == (3, 8, 8, 1)


def test_frame_folder_overwrite_never_deletes_other_files(tmp_path):
    frames = np.zeros((2, 4, 4))
    out = tmp_path / "out"
    out.mkdir()
    (out / "input.png").write_bytes(b"the user's own file")
    with pytest.raises(FileExistsError, match="did not write"):
        save_frames(out, frames, overwrite=True)
    assert (out / "input.png").read_bytes() == b"the user's own file"
    # a folder of earlier frames is replaced whole: three frames become two
    save_frames(tmp_path / "seq", np.ones((3, 4, 4)))
    save_frames(tmp_path / "seq", frames, overwrite=True)
    assert sorted(p.name for p in (tmp_path / "seq").iterdir()) == ["frame_0000.png", "frame_0001.png"]
    assert load_frames(tmp_path / "seq").max() == 0.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "seq"]  # no temporary folders left


def test_failed_frame_write_keeps_the_old_sequence(tmp_path, monkeypatch):
    import imageio.v3 as iio

    save_frames(tmp_path / "seq", np.ones((2, 4, 4)))
    calls = []

    def failing_imwrite(target, *args, **kwargs):
        calls.append(target)
        if len(calls) == 2:
            raise OSError("disk full")
        return real(target, *args, **kwargs)

    real = iio.imwrite
    monkeypatch.setattr(iio, "imwrite", failing_imwrite)
    with pytest.raises(OSError, match="disk full"):
        save_frames(tmp_path / "seq", np.zeros((3, 4, 4)), overwrite=True)
    monkeypatch.undo()
    assert load_frames(tmp_path / "seq").min() == 1.0  # the old frames are untouched
    assert [p.name for p in tmp_path.iterdir()] == ["seq"]  # no temporary folder left


def test_video_without_the_extra_says_how_to_get_it(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None if name == "imageio_ffmpeg" else real(name))
    with pytest.raises(ValueError, match=r"pip install 'imageio-ffmpeg'"):
        save_frames(tmp_path / "v.mp4", np.zeros((3, 8, 8)))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("suffix", [".mp4", ".mov", ".avi", ".mkv", ".mpeg", ".wmv"])
def test_every_video_suffix_round_trips(tmp_path, suffix):
    pytest.importorskip("imageio_ffmpeg")  # in the test extra, so CI runs this
    frames = np.stack([np.roll(data.load("bumpy")[:32, :32], 2 * t, axis=1) for t in range(6)])
    back = load_frames(save_frames(tmp_path / f"v{suffix}", frames, fps=6))
    assert back.shape == (6, 32, 32, 3)
    assert np.abs(back - frames).mean() < 0.1  # lossy codec: colours close, not exact


@pytest.mark.parametrize("suffix", [".m4v", ".mpg", ".flv", ".webm"])
def test_video_suffixes_the_writer_cannot_fill_are_refused_up_front(tmp_path, suffix):
    with pytest.raises(ValueError, match=r"\.mp4"):  # the message lists the suffixes that work
        save_frames(tmp_path / f"v{suffix}", np.zeros((3, 8, 8)))
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- #
# reliability audit: permissions, signals, argument checks, odd files
# --------------------------------------------------------------------------- #
def _mode(path):
    return path.stat().st_mode & 0o777


@POSIX
def test_new_files_get_the_permissions_the_umask_gives(tmp_path):
    old = os.umask(0o022)
    try:
        written = [save_image(tmp_path / "a.png", np.zeros((4, 4))), save_image(tmp_path / "a.npy", np.zeros((4, 4))),
                   save_image(tmp_path / "a.tif", np.zeros((4, 4))), save_frames(tmp_path / "a.gif", np.zeros((2, 4, 4)))]
        folder = save_frames(tmp_path / "seq", np.zeros((2, 4, 4)))
        os.umask(0o027)
        strict = save_image(tmp_path / "b.png", np.zeros((4, 4)))
        strict_folder = save_frames(tmp_path / "seq2", np.zeros((2, 4, 4)))
    finally:
        os.umask(old)
    assert [_mode(p) for p in written] == [0o644] * 4
    assert _mode(folder) == 0o755 and {_mode(p) for p in folder.iterdir()} == {0o644}
    assert _mode(strict) == 0o640 and _mode(strict_folder) == 0o750
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.gif", "a.npy", "a.png", "a.tif", "b.png", "seq", "seq2"]


@POSIX
def test_overwriting_keeps_the_mode_of_the_replaced_file(tmp_path):
    path = save_image(tmp_path / "a.png", np.zeros((4, 4)))
    os.chmod(path, 0o604)  # a mode no umask gives by itself
    save_image(path, np.ones((4, 4)), overwrite=True)
    assert _mode(path) == 0o604 and load_image(path).min() == 1.0
    folder = save_frames(tmp_path / "seq", np.zeros((2, 4, 4)))
    os.chmod(folder, 0o705)
    save_frames(folder, np.ones((3, 4, 4)), overwrite=True)
    assert _mode(folder) == 0o705 and len(list(folder.iterdir())) == 3


_SLOW_WRITE = """
import signal, sys, time
import numpy as np
import texsynth.io as tio
from texsynth.io import _frames, _images

mode, target = sys.argv[1], sys.argv[2]
if mode == "own-handler":
    signal.signal(signal.SIGTERM, lambda *args: sys.exit(3))
real = _images.imwrite  # writes the encoded image to the temporary file
calls = []


def slow_imwrite(uri, image, **kwargs):
    calls.append(uri)
    if mode == "frames" and len(calls) == 1:
        return real(uri, image, **kwargs)  # the first frame is complete, the second never ends
    with open(uri, "wb") as f:
        f.write(b"half an image")
    print("writing", flush=True)
    while True:
        time.sleep(0.05)


_images.imwrite = _frames.imwrite = slow_imwrite
if mode == "frames":
    tio.save_frames(target, np.zeros((3, 8, 8)), overwrite=True)
else:
    tio.save_image(target, np.zeros((8, 8)), overwrite=True)
"""


@POSIX
@pytest.mark.parametrize("mode, name, returncode", [
    ("image", "noise.png", -signal.SIGTERM),   # terminated by SIGTERM, as without texsynth's handler
    ("frames", "seq", -signal.SIGTERM),
    ("own-handler", "noise.png", 3),           # a program's own SIGTERM handler still decides
])
def test_sigterm_during_a_write_leaves_no_temporary_file(tmp_path, mode, name, returncode):
    out = tmp_path / "out"
    out.mkdir()
    target = out / name
    # an earlier result, which the interrupted overwrite must leave intact
    save_frames(target, np.ones((2, 8, 8))) if mode == "frames" else save_image(target, np.ones((8, 8)))
    script = tmp_path / "slow_write.py"
    script.write_text(_SLOW_WRITE)
    assert interrupt_writer([script, mode, target], signal.SIGTERM) == returncode
    assert [p.name for p in out.iterdir()] == [name]  # no hidden temporary file or folder
    back = load_frames(target) if mode == "frames" else load_image(target)
    assert back.min() == 1.0 and back.shape[0] == (2 if mode == "frames" else 8)


def _dead_pid():
    """The pid of a process that has ended (a writer killed with ``kill -9``)."""
    proc = subprocess.Popen([sys.executable, "-c", ""])
    proc.wait()
    return proc.pid


def test_the_next_save_removes_what_a_killed_writer_left(tmp_path):
    # kill -9 allows no clean-up: a hidden temporary file or frame folder stays, named after the target and
    # the writer's pid. The next save of the same target removes those whose writer is no longer running.
    dead = _dead_pid()
    (tmp_path / f".noise-{dead}-0123abcd.png").write_bytes(b"half an image")
    (tmp_path / f".seq-{dead}-0123abcd").mkdir()
    (tmp_path / f".seq-{dead}-0123abcd" / "frame_0000.png").write_bytes(b"half a frame")
    others = [
        f".noise-{os.getpid()}-0123abcd.png",  # a live writer's (this process)
        f".noise-{dead}-0123abc.png", f".noise-{dead}-0123abcd.png.part", f".noise-{dead}-0123abcd.jpg",
        f".noisy-{dead}-0123abcd.png", f"noise-{dead}-0123abcd.png", f".seq-{dead}-0123abcd.png",
        ".noise-0123abcd.png",  # no pid: its writer cannot be told dead
    ]
    for name in others:
        (tmp_path / name).write_bytes(b"someone else's")
    (tmp_path / f".noise-{dead}-89abcdef.png").mkdir()  # a folder, where a file temporary is a file
    others.append(f".noise-{dead}-89abcdef.png")
    save_image(tmp_path / "noise.png", np.zeros((4, 4)))
    save_frames(tmp_path / "seq", np.zeros((2, 4, 4)))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(others + ["noise.png", "seq"])
    assert all((tmp_path / name).is_dir() or (tmp_path / name).read_bytes() == b"someone else's" for name in others)


_FULL_DISK = """
import resource, signal, sys
import numpy as np
from texsynth.cli import main
from texsynth.io import save_frames, save_image

# past the file-size limit a write fails (EFBIG) as one on a full disk does (ENOSPC)
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))
noise = np.random.default_rng(0).random((3, 64, 64, 3))
folder, images, frames = sys.argv[1], sys.argv[2].split(","), sys.argv[3].split(",")
for name in images + frames:
    try:
        save_image(folder + name, noise[0]) if name in images else save_frames(folder + name, noise)
    except OSError:
        print("failed", name)
    else:
        print("wrote", name)
sys.exit(main(["perlin", "-o", folder + "cli.png", "--size", "256x256"]))
"""


@POSIX
def test_a_full_disk_gives_one_error_and_nothing_else(tmp_path):
    script = tmp_path / "full_disk.py"
    script.write_text(_FULL_DISK)
    out = tmp_path / "out"
    out.mkdir()
    images, frames = ["i.png", "i.jpg", "i.bmp", "i.tif"], ["a.gif", "a.png", "seq"]
    proc = subprocess.run([sys.executable, str(script), f"{out}/", ",".join(images), ",".join(frames)],
                          capture_output=True, text=True, timeout=120)
    assert proc.stdout.splitlines() == [f"failed {name}" for name in images + frames]  # no truncated JPEG passes
    assert proc.returncode == 2
    assert proc.stderr.startswith("texsynth: error:") and len(proc.stderr.splitlines()) == 1, proc.stderr
    assert list(out.iterdir()) == []


_FULL_DISK_VIDEO = """
import resource, signal, sys
import numpy as np
from texsynth.io import save_frames

signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))
noise = np.random.default_rng(0).random((3, 64, 64, 3))
for name in sys.argv[2:]:
    try:
        save_frames(sys.argv[1] + name, noise)
    except OSError:
        print("failed", name)
    else:
        print("wrote", name)
"""


@POSIX
def test_a_video_on_a_full_disk_is_an_oserror_and_leaves_nothing(tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    script = tmp_path / "full_disk_video.py"
    script.write_text(_FULL_DISK_VIDEO)
    out = tmp_path / "out"
    out.mkdir()
    names = ["v.mp4", "v.mkv"]  # MP4 writes its index last; Matroska streams its frames
    proc = subprocess.run([sys.executable, str(script), f"{out}/", *names], capture_output=True, text=True,
                          timeout=120)
    assert proc.stdout.splitlines() == [f"failed {name}" for name in names], proc.stderr[-2000:]
    assert list(out.iterdir()) == []


def test_a_tiff_claiming_a_huge_size_is_refused_before_reading_it(tmp_path, monkeypatch):
    import struct

    import tifffile

    path = tmp_path / "huge.tif"
    tifffile.imwrite(path, np.zeros((4, 4), np.uint8), metadata=None)
    with tifffile.TiffFile(path) as tif:
        tags = tif.pages[0].tags
        names = ("ImageWidth", "ImageLength", "RowsPerStrip")  # one strip, of 100000 rows
        offsets = [tags[name].valueoffset for name in names]
        assert all(tags[name].dtype == 4 for name in names)  # LONG: 4 bytes
    raw = bytearray(path.read_bytes())
    for offset in offsets:
        raw[offset : offset + 4] = struct.pack("<I", 100_000)
    path.write_bytes(bytes(raw))
    decoded = []
    monkeypatch.setattr(tifffile.TiffFile, "asarray", lambda *a, **k: decoded.append(1))
    monkeypatch.setattr(tifffile.TiffPage, "asarray", lambda *a, **k: decoded.append(1))
    with pytest.raises(ValueError, match=r"huge\.tif.* 100000 x 100000 .*limit"):
        load_image(path)
    assert not decoded  # refused from the header: nothing read, nothing allocated


@pytest.mark.parametrize("bad", [None, 3, ["a.png"], 2.5, True])
def test_a_path_of_the_wrong_type_is_a_typeerror_naming_path(tmp_path, bad):
    for call in (load_image, load_frames, lambda p: save_image(p, np.zeros((2, 2))),
                 lambda p: save_frames(p, np.zeros((2, 2, 2)))):
        with pytest.raises(TypeError, match=r"path must be a str or os\.PathLike"):
            call(bad)
    with pytest.raises(ValueError, match="path is an empty string"):
        save_image("", np.zeros((2, 2)))


@pytest.mark.parametrize("fps, error", [(float("nan"), ValueError), (-5, ValueError), (0, ValueError),
                                        (float("inf"), ValueError), (True, TypeError), ("12", TypeError)])
def test_fps_must_be_finite_and_positive(tmp_path, fps, error):
    for target in ("a.gif", "seq"):
        with pytest.raises(error, match="fps"):
            save_frames(tmp_path / target, np.zeros((2, 4, 4)), fps=fps)
    with pytest.raises(ValueError, match="too slow for a GIF"):
        save_frames(tmp_path / "slow.gif", np.zeros((2, 4, 4)), fps=0.001)
    assert list(tmp_path.iterdir()) == []


def test_flags_must_be_bools(tmp_path):
    path = save_image(tmp_path / "a.png", np.zeros((4, 4)))
    with pytest.raises(TypeError, match="overwrite must be True or False"):
        save_image(path, np.ones((4, 4)), overwrite="no")  # a truthy string must not overwrite
    assert load_image(path).max() == 0.0
    with pytest.raises(TypeError, match="loop"):
        save_frames(tmp_path / "a.gif", np.zeros((2, 4, 4)), loop="no")


def test_cmyk_files_load_as_rgb(tmp_path):
    from PIL import Image

    rgb = np.zeros((16, 16, 3), np.uint8)
    rgb[:8] = (200, 100, 50)
    rgb[8:] = (20, 180, 240)
    for name in ("cmyk.jpg", "cmyk.tif"):
        Image.fromarray(rgb).convert("CMYK").save(tmp_path / name, quality=100)
        assert iio.imread(tmp_path / name).shape[-1] == 4  # what imageio gives: C, M, Y and K as "alpha"
        image = load_image(tmp_path / name)
        assert image.shape == (16, 16, 3)
        assert np.abs(image - rgb / 255).max() < 8 / 255  # JPEG is lossy; the TIFF is exact


@pytest.mark.parametrize("dtype", [np.int32, np.int16, np.uint32, np.int64])
def test_integer_files_without_a_white_level_are_refused(tmp_path, dtype):
    path = tmp_path / "counts.tif"
    iio.imwrite(path, np.array([[1000, 5], [0, 7]], dtype=dtype))
    with pytest.raises(ValueError, match=f"holds {np.dtype(dtype).name} pixels.*no agreed white level") as info:
        load_image(path)
    assert "counts.tif" in str(info.value)


def test_sixteen_bit_netpbm_is_scaled_by_65535_even_when_dark(tmp_path):
    # Pillow decodes 16-bit PGM as int32 0..65535; a dark one (max <= 255) used to be read as 8-bit
    values = np.array([[0, 1, 100], [200, 3, 7]])
    path = tmp_path / "dark.pgm"
    path.write_bytes(b"P5\n3 2\n65535\n" + values.astype(">u2").tobytes())
    assert np.array_equal(load_image(path), values / 65535)


def test_gif_alpha_is_dropped_and_transparent_gifs_load(tmp_path):
    rng = np.random.default_rng(0)
    rgba = rng.random((3, 8, 8, 4))
    back = load_frames(save_frames(tmp_path / "a.gif", rgba))
    assert back.shape == (3, 8, 8, 3)
    # a GIF another tool wrote with transparency: decoded as RGB and RGBA frames
    raw = (rng.random((3, 8, 8, 4)) * 255).astype(np.uint8)
    iio.imwrite(tmp_path / "t.gif", raw, extension=".gif", duration=100, loop=0)
    assert load_frames(tmp_path / "t.gif").shape[:3] == (3, 8, 8)


def test_formats_without_alpha_or_sixteen_bit_colour(tmp_path):
    la = np.random.default_rng(0).random((6, 7, 2))
    for suffix in (".bmp", ".ppm"):
        back = load_image(save_image(tmp_path / f"la{suffix}", la))  # alpha dropped, as for JPEG
        assert back.shape == (6, 7) and np.abs(back - la[..., 0]).max() <= 0.5 / 255 + 1e-9
    with pytest.raises(ValueError, match="bits=16 needs a .png, .tif or .exr"):
        save_image(tmp_path / "c16.jpg", np.zeros((4, 4, 3)), bits=16)
    with pytest.raises(ValueError, match="bits=32.*needs a .tif"):
        save_image(tmp_path / "c32.png", np.zeros((4, 4, 3)), bits=32)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["la.bmp", "la.ppm"]


_DEPTHS = {8: (np.uint8, 255), 16: (np.uint16, 65535), 32: (np.float32, 1)}


@pytest.mark.parametrize("channels", [None, 2, 3, 4])
@pytest.mark.parametrize("bits, suffix", [(8, ".png"), (16, ".png"), (8, ".tif"), (16, ".tif"), (32, ".tif")])
def test_round_trips_of_every_depth_and_layout_are_exact(tmp_path, channels, bits, suffix):
    rng = np.random.default_rng(bits + (channels or 1))
    shape = (9, 11) if channels is None else (9, 11, channels)
    kind, white = _DEPTHS[bits]
    pixels = rng.random(shape).astype(np.float32) if bits == 32 else rng.integers(0, white + 1, shape).astype(kind)
    path = save_image(tmp_path / f"x{suffix}", pixels, bits=bits)
    back = load_image(path)
    assert back.shape == shape and back.dtype == (np.float32 if bits == 32 else np.float64)
    assert np.array_equal(back, pixels / np.float64(white) if bits != 32 else pixels)
    assert image_bits(path) == bits
    if bits != 32:  # float in, the same integers out
        assert np.array_equal(load_image(save_image(tmp_path / f"y{suffix}", back, bits=bits)), back)


def _png16(path, pixels, filters):
    """A 16-bit PNG whose rows use the given filter types (1 Sub, 2 Up, 3 Average, 4 Paeth), as libpng writes."""
    import struct
    import zlib

    h, w, c = pixels.shape
    raw = np.ascontiguousarray(pixels, ">u2").reshape(h, w * c).view(np.uint8).astype(np.int32)
    bpp, lines = 2 * c, []
    for r in range(h):
        x, prior, kind = raw[r], raw[r - 1] if r else np.zeros_like(raw[0]), filters[r % len(filters)]
        left = np.r_[np.zeros(bpp, np.int32), x[:-bpp]]
        corner = np.r_[np.zeros(bpp, np.int32), prior[:-bpp]]
        p = left + prior - corner
        pa, pb, pc = np.abs(p - left), np.abs(p - prior), np.abs(p - corner)
        paeth = np.where((pa <= pb) & (pa <= pc), left, np.where(pb <= pc, prior, corner))
        pred = {0: 0, 1: left, 2: prior, 3: (left + prior) // 2, 4: paeth}[kind]
        lines.append(bytes([kind]) + ((x - pred) & 0xFF).astype(np.uint8).tobytes())

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    colour = {2: 4, 3: 2, 4: 6}[c]
    Path(path).write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, colour, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(b"".join(lines))) + chunk(b"IEND", b""))


@pytest.mark.parametrize("filters", [(1,), (2,), (3,), (4,), (0, 1, 2, 3, 4)])
def test_sixteen_bit_colour_png_of_other_writers_is_read_exactly(tmp_path, filters):
    # other tools (libpng, Substance, Photoshop) filter rows adaptively; Pillow reads such files as 8 bits
    pixels = (np.random.default_rng(0).random((13, 17, 3)) * 65535).astype(np.uint16)
    pixels[:, :8] = np.linspace(0, 65535, 8).astype(np.uint16)[None, :, None]  # smooth runs too
    _png16(tmp_path / "f.png", pixels, filters)
    assert np.array_equal(load_image(tmp_path / "f.png"), pixels / 65535.0)


def test_the_png_row_filters_match_pillows_decoder(tmp_path):
    from texsynth.io._formats import _unfilter

    rng = np.random.default_rng(1)
    image = (np.linspace(0, 200, 64)[None, :, None] + rng.integers(0, 50, (40, 64, 3))).astype(np.uint8)
    iio.imwrite(tmp_path / "p.png", image)  # Pillow chooses a filter per row
    import zlib

    raw = (tmp_path / "p.png").read_bytes()
    body, at = b"", 8
    while at < len(raw):
        length, kind = int.from_bytes(raw[at:at + 4], "big"), raw[at + 4:at + 8]
        body += raw[at + 8:at + 8 + length] if kind == b"IDAT" else b""
        at += 12 + length
    rows = np.frombuffer(zlib.decompress(body), np.uint8).reshape(40, -1)
    assert len(set(rows[:, 0].tolist())) > 1  # several filter types in use
    assert np.array_equal(_unfilter(rows, 40, 64 * 3, 3).reshape(40, 64, 3), image)


def test_npy_suffix_in_capitals_and_folder_targets(tmp_path):
    volume = np.random.default_rng(0).random((3, 4, 5))
    path = save_image(tmp_path / "V.NPY", volume)
    assert np.array_equal(np.load(path), volume)
    assert [p.name for p in tmp_path.iterdir()] == ["V.NPY"]
    (tmp_path / "d.png").mkdir()
    with pytest.raises(FileExistsError, match="is a folder"):
        save_image(tmp_path / "d.png", np.zeros((2, 2)), overwrite=True)
    with pytest.raises(ValueError, match="not a frame-sequence format"):
        save_frames(tmp_path / "f.tif", np.zeros((2, 4, 4)))


def test_animated_png_keeps_alpha_and_needs_no_video_extra(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None if name == "imageio_ffmpeg" else real(name))
    frames = np.random.default_rng(0).random((3, 8, 10, 4))
    back = load_frames(save_frames(tmp_path / "a.png", frames, fps=5))
    assert back.shape == (3, 8, 10, 4) and np.abs(back - frames).max() <= 0.5 / 255 + 1e-9


# bad values of every parameter of the public functions; each must be refused with a
# TypeError/ValueError naming the parameter, and leave nothing behind
_BAD_FLOATS = st.sampled_from([np.nan, np.inf, -np.inf, -0.5, 1.5, 255.0])
_BAD_ARRAYS = st.one_of(
    st.none(), st.text(max_size=3), st.just([[0.1], [0.2, 0.3]]),
    hnp.arrays(np.float64, st.tuples(st.integers(1, 5), st.integers(1, 5)), elements=_BAD_FLOATS),
    hnp.arrays(st.sampled_from([np.int64, np.int8, np.complex128]), st.tuples(st.integers(1, 5), st.integers(1, 5))),
    st.tuples(st.integers(0, 3), st.integers(0, 3)).filter(lambda s: 0 in s).map(np.zeros),
)
_BAD_IMAGES = st.one_of(_BAD_ARRAYS, st.integers(), st.booleans(),
                        st.sampled_from([(5,), (2, 2, 5), (1, 2, 2, 2, 1)]).map(np.zeros))
_BAD_FRAMES = st.one_of(_BAD_ARRAYS, st.sampled_from([(5,), (2, 2, 2, 5), (1, 2, 2, 2, 1, 1)]).map(np.zeros))
_BAD_PATHS = st.one_of(st.none(), st.integers(), st.floats(), st.booleans(), st.just(""),
                       st.lists(st.text(max_size=3), max_size=2))
_NOT_BOOLS = st.one_of(st.none(), st.integers(), st.text(max_size=3), st.floats())
_BAD_FPS = st.one_of(st.none(), st.booleans(), st.text(max_size=3), st.floats(max_value=0), st.just(np.nan),
                     st.just(np.inf))
_BAD_BITS = st.one_of(st.none(), st.booleans(), st.text(max_size=3), st.floats(), st.integers().filter(lambda b: b not in (8, 16)))

_IO_CASES = {
    "load_image path": (lambda v, d: load_image(v), "path", _BAD_PATHS),
    "load_frames path": (lambda v, d: load_frames(v), "path", _BAD_PATHS),
    "save_image path": (lambda v, d: save_image(v, np.zeros((2, 2))), "path", _BAD_PATHS),
    "save_image image": (lambda v, d: save_image(d / "a.png", v), "image", _BAD_IMAGES),
    "save_image npy": (lambda v, d: save_image(d / "a.npy", v), "image", _BAD_ARRAYS),
    "save_image bits": (lambda v, d: save_image(d / "a.png", np.zeros((2, 2)), bits=v), "bits", _BAD_BITS.filter(lambda b: b is not None)),
    "save_image overwrite": (lambda v, d: save_image(d / "a.png", np.zeros((2, 2)), overwrite=v), "overwrite", _NOT_BOOLS),
    "save_frames path": (lambda v, d: save_frames(v, np.zeros((2, 2, 2))), "path", _BAD_PATHS),
    "save_frames frames": (lambda v, d: save_frames(d / "a.gif", v), "frames", _BAD_FRAMES),
    "save_frames folder": (lambda v, d: save_frames(d / "seq", v), "frames", _BAD_FRAMES),
    "save_frames fps": (lambda v, d: save_frames(d / "a.gif", np.zeros((2, 2, 2)), fps=v), "fps", _BAD_FPS),
    "save_frames loop": (lambda v, d: save_frames(d / "a.gif", np.zeros((2, 2, 2)), loop=v), "loop", _NOT_BOOLS),
    "save_frames overwrite": (lambda v, d: save_frames(d / "seq", np.zeros((2, 2, 2)), overwrite=v), "overwrite", _NOT_BOOLS),
    "to_uint image": (lambda v, d: to_uint(v), "image", _BAD_ARRAYS),
    "to_uint bits": (lambda v, d: to_uint(np.zeros(2), v), "bits", _BAD_BITS),
}


@pytest.mark.parametrize("case", sorted(_IO_CASES))
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_bad_input_is_refused_naming_the_parameter(case, data):
    call, name, strategy = _IO_CASES[case]
    value = data.draw(strategy, label=name)
    with tempfile.TemporaryDirectory() as d:
        with pytest.raises((TypeError, ValueError)) as info:
            call(value, Path(d))
        assert name in str(info.value)
        assert os.listdir(d) == []


# --------------------------------------------------------------------------- EXR, TGA, ranges (issue 34)
import importlib.util  # noqa: E402

from texsynth.io import load_coordinates, normalize_range, restore_range, save_coordinates  # noqa: E402

# the exr extra is optional: its tests run where it is installed (the test extra installs it)
needs_exr = pytest.mark.skipif(importlib.util.find_spec("OpenEXR") is None,
                               reason="the exr extra (OpenEXR) is not installed")


@needs_exr
@pytest.mark.parametrize("channels", [None, 2, 3, 4])
def test_exr_round_trips_float32_exactly_and_half_to_half_precision(tmp_path, channels):
    shape = (9, 11) if channels is None else (9, 11, channels)
    values = (np.random.default_rng(channels or 1).random(shape) * 7 - 2).astype(np.float32)  # heights: [-2, 5]
    path = save_image(tmp_path / "h.exr", values)
    assert image_bits(path) == 32
    with pytest.raises(ValueError, match="normalize=True"):  # outside [0, 1]: the library's contract
        load_image(path)
    unit, value_range = load_image(path, normalize=True)
    assert unit.dtype == np.float32 and unit.shape == shape and 0 <= unit.min() and unit.max() <= 1
    assert value_range == (float(values.min()), float(values.max()))
    assert np.abs(restore_range(unit, value_range) - values).max() <= 4 * np.finfo(np.float32).eps * 7
    import OpenEXR

    channels_in_file = set(OpenEXR.File(str(path)).channels()) | set(
        OpenEXR.File(str(path), separate_channels=True).channels())
    assert {"Y", "R", "RGB", "RGBA"} & channels_in_file  # named as viewers expect
    half = save_image(tmp_path / "h16.exr", values, bits=16)
    assert image_bits(half) == 16
    back = restore_range(*load_image(half, normalize=True))
    assert np.allclose(back, values, rtol=2 ** -10, atol=2 ** -10)
    in_range = np.clip(values, 0, 1)
    assert np.array_equal(load_image(save_image(tmp_path / "u.exr", in_range)), in_range)


@needs_exr
def test_exr_channels_that_are_read_and_refused(tmp_path):
    import OpenEXR

    def write(name, channels):
        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        OpenEXR.File(header, {k: v.astype(np.float32) for k, v in channels.items()}).write(str(tmp_path / name))
        return tmp_path / name

    plane = np.random.default_rng(0).random((5, 6))
    assert np.allclose(load_image(write("z.exr", {"Z": plane})), plane)  # one channel: grey, whatever its name
    layered = write("l.exr", {"R": plane, "G": plane / 2, "B": plane / 4, "depth.Z": plane * 9})
    assert load_image(layered).shape == (5, 6, 3)  # R, G, B read; other layers left
    with pytest.raises(ValueError, match=r"\['G', 'R'\].*R, G, B"):
        load_image(write("rg.exr", {"R": plane, "G": plane}))
    (tmp_path / "bad.exr").write_bytes(b"v/1\x01 not really")
    with pytest.raises(ValueError, match="cannot read .* as an OpenEXR image"):
        load_image(tmp_path / "bad.exr")


@needs_exr
def test_exr_bits_that_cannot_be_stored_are_refused_before_writing(tmp_path):
    with pytest.raises(ValueError, match="bits=8 cannot be stored in an .exr"):
        save_image(tmp_path / "a.exr", np.zeros((4, 4)), bits=8)
    with pytest.raises(ValueError, match="largest half float"):
        save_image(tmp_path / "b.exr", np.full((4, 4), 1e5), bits=16)
    with pytest.raises(ValueError, match="NaN or infinite"):
        save_image(tmp_path / "c.exr", np.array([[0.0, np.inf]]))
    assert not list(tmp_path.iterdir())


def test_exr_without_the_extra_names_it_and_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "OpenEXR", None)  # as if it were not installed
    with pytest.raises(ImportError, match=r"pip install 'OpenEXR>=3.3'"):
        save_image(tmp_path / "a.exr", np.zeros((4, 4)))
    (tmp_path / "in.exr").write_bytes(b"\x76\x2f\x31\x01" + bytes(60))
    with pytest.raises(ImportError, match="OpenEXR"):
        load_image(tmp_path / "in.exr")
    from texsynth.io._images import check_suffix

    with pytest.raises(ImportError, match="exr"):
        check_suffix("out.exr")  # what the command line asks before a synthesis
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.exr"]


@pytest.mark.parametrize("channels", [None, 2, 3, 4])
def test_tga_round_trips_at_8_bits_with_alpha(tmp_path, channels):
    shape = (7, 9) if channels is None else (7, 9, channels)
    pixels = np.random.default_rng(3).integers(0, 256, shape).astype(np.uint8)
    path = save_image(tmp_path / "t.tga", pixels)
    assert image_bits(path) == 8
    assert np.array_equal(load_image(path), pixels / 255.0)
    assert load_frames(tmp_path).shape[:3] == (1, 7, 9)  # a folder of TGA frames is a sequence too


def test_float_files_outside_the_unit_range_pass_through_float_formats(tmp_path):
    heights = np.array([[-0.25, 0.0, 0.5], [1.0, 2.5, 3.75]])
    stored = iio.imread(save_image(tmp_path / "h.tif", heights, bits=32))
    assert np.array_equal(stored, heights.astype(np.float32))  # kept as they are, not clipped
    with pytest.raises(ValueError, match=r"values in \[-0.25, 3.75\] but a .png file stores \[0, 1\].*\.exr"):
        save_image(tmp_path / "h.png", heights)
    with pytest.raises(ValueError, match=r"\[-0.25, 3.75\].*normalize=True"):
        load_image(tmp_path / "h.tif")
    unit, value_range = load_image(tmp_path / "h.tif", normalize=True)
    assert value_range == (-0.25, 3.75) and unit.min() == 0 and unit.max() == 1
    assert np.allclose(restore_range(unit, value_range), heights, atol=1e-6)
    # files in [0, 1] (every integer file, float files inside it) come back unchanged, with (0, 1)
    ramp = np.linspace(0, 1, 12).reshape(3, 4)
    for path in (save_image(tmp_path / "r.png", ramp, bits=16), save_image(tmp_path / "r.tif", ramp, bits=32)):
        image, value_range = load_image(path, normalize=True)
        assert value_range == (0.0, 1.0) and np.array_equal(image, load_image(path))


def test_normalize_range_and_restore_range():
    data_ = np.array([[-1.5, 0.5], [2.5, 6.5]], dtype=np.float32)
    unit, value_range = normalize_range(data_)
    assert unit.dtype == np.float32 and value_range == (-1.5, 6.5)
    assert unit.tolist() == [[0.0, 0.25], [0.5, 1.0]]
    assert np.array_equal(restore_range(unit, value_range), data_)
    shared, r = normalize_range(data_, (-2.0, 8.0))  # a range several files share
    assert r == (-2.0, 8.0) and np.allclose(shared * 10 - 2, data_)
    inside = np.array([[0.2, 0.4]])
    assert normalize_range(inside)[1] == (0.0, 1.0) and np.array_equal(normalize_range(inside)[0], inside)
    assert normalize_range(np.array([[0, 255]], np.uint8))[0].tolist() == [[0.0, 1.0]]
    constant, r = normalize_range(np.full((2, 2), 5.0))
    assert np.array_equal(restore_range(constant, r), np.full((2, 2), 5.0))
    with pytest.raises(ValueError, match=r"outside value_range=\(0, 2\)"):
        normalize_range(data_, (0, 2))
    with pytest.raises(ValueError, match="low < high"):
        normalize_range(data_, (3, 3))
    with pytest.raises(TypeError, match="value_range must be a pair"):
        restore_range(unit, "wide")
    with pytest.raises(ValueError, match="NaN or infinite"):
        normalize_range(np.array([[np.nan, 1.0]]))
    with pytest.raises(ValueError, match=r"shape \(H, W\) or \(H, W, C\)"):
        normalize_range(np.zeros((2, 2, 7)))


# --------------------------------------------------------------------------- coordinate maps as images
def _copy_map(shape, size, seed=0):
    rng = np.random.default_rng(seed)
    return np.stack([rng.integers(0, size[0], shape), rng.integers(0, size[1], shape)], axis=-1)


@pytest.mark.parametrize("suffix", [".png", ".tif", pytest.param(".exr", marks=needs_exr)])
def test_coordinate_maps_as_images_round_trip_exactly(tmp_path, suffix):
    for size in ((1, 1), (48, 40), (255, 7), (4097, 1000), (32768, 32768)):
        coords = _copy_map((12, 15), size, seed=size[0])
        coords[0, 0], coords[0, 1] = (size[0] - 1, size[1] - 1), (0, 0)  # both ends of the exemplar
        path = save_coordinates(tmp_path / f"m{suffix}", coords, exemplar_size=size, overwrite=True)
        saved = load_coordinates(path)
        assert saved.coordinates.dtype == np.int64 and np.array_equal(saved.coordinates, coords)
        assert saved.weights is None and saved.source_index is None
    # the values a shader reads: R = (col + 0.5) / width, G = (row + 0.5) / height, B = 0
    coords = _copy_map((6, 5), (48, 40))
    rgb = load_image(save_coordinates(tmp_path / f"s{suffix}", coords, exemplar_size=(48, 40)))
    assert rgb.shape == (6, 5, 3) and np.all(rgb[..., 2] == 0)
    tolerance = 0.5 / 65535 if suffix == ".png" else 1e-7
    assert np.abs(rgb[..., 0] - (coords[..., 1] + 0.5) / 40).max() <= tolerance
    assert np.abs(rgb[..., 1] - (coords[..., 0] + 0.5) / 48).max() <= tolerance
    if suffix == ".png":
        assert image_bits(tmp_path / "s.png") == 16
    # pixels without a source (-1: Efros-Leung's given pixels) get an alpha channel, 0 there
    coords[2, 3] = -1
    rgba = load_image(save_coordinates(tmp_path / f"a{suffix}", coords, exemplar_size=(48, 40)))
    assert rgba.shape == (6, 5, 4) and rgba[2, 3, 3] == 0 and rgba[..., 3].sum() == 29
    assert np.array_equal(load_coordinates(tmp_path / f"a{suffix}").coordinates, coords)


def test_coordinate_map_images_of_a_synthesis_render_it(tmp_path):
    import texsynth

    exemplar = data.load("bread")[:40, :36]
    out, info = texsynth.quilt(exemplar, (50, 60), block=12, rng=0, return_info=True)
    saved = load_coordinates(save_coordinates(tmp_path / "q.png", info, exemplar_size=exemplar.shape[:2]))
    assert np.array_equal(texsynth.apply_coordinates(exemplar, saved), out)
    # a blend map is stored as its dominant source: the copy map coordinates[:, :, 0]
    out, info = texsynth.patch_sampling(exemplar, 48, block=12, rng=0, return_info=True)
    dominant = load_coordinates(save_coordinates(tmp_path / "p.tif", info, exemplar_size=exemplar.shape[:2]))
    assert np.array_equal(dominant.coordinates, info.coordinates[:, :, 0])


def test_coordinate_map_images_refuse_what_they_cannot_hold(tmp_path):
    coords = _copy_map((6, 5), (48, 40))
    with pytest.raises(ValueError, match=r"exemplar_size=exemplar.shape\[:2\]"):
        save_coordinates(tmp_path / "m.png", coords)
    with pytest.raises(ValueError, match="outside the exemplar of exemplar_size"):
        save_coordinates(tmp_path / "m.png", coords, exemplar_size=(10, 10))
    with pytest.raises(ValueError, match="several exemplars.*as .npz"):
        save_coordinates(tmp_path / "m.png", coords[:, :, None], np.ones((6, 5, 1)),
                         source_index=np.zeros((6, 5, 1), int), exemplar_size=(48, 40))
    with pytest.raises(ValueError, match=r"up to 32768 pixels.*\.exr or \.tif"):
        save_coordinates(tmp_path / "m.png", coords, exemplar_size=(40000, 40))
    with pytest.raises(ValueError, match=r"\.npz.*\.png \(16 bits\)"):
        save_coordinates(tmp_path / "m.jpg", coords, exemplar_size=(48, 40))
    with pytest.raises(ValueError, match="exemplar_size must be"):
        save_coordinates(tmp_path / "m.png", coords, exemplar_size=(48, 0))
    assert not list(tmp_path.iterdir())  # nothing written
    # a map re-saved by another program (no note of the exemplar size) needs it given; a note must agree
    path = save_coordinates(tmp_path / "m.png", coords, exemplar_size=(48, 40))
    plain = save_image(tmp_path / "plain.png", load_image(path), bits=16)
    with pytest.raises(ValueError, match="does not record the exemplar's size"):
        load_coordinates(plain)
    assert np.array_equal(load_coordinates(plain, exemplar_size=(48, 40)).coordinates, coords)
    with pytest.raises(ValueError, match="a map of an exemplar of 40x48 pixels"):
        load_coordinates(path, exemplar_size=(50, 50))
    with pytest.raises(ValueError, match="8-bit image"):
        load_coordinates(save_image(tmp_path / "m8.png", load_image(path)), exemplar_size=(300, 300))
    with pytest.raises(ValueError, match="exemplar_size is for image maps"):
        load_coordinates(save_coordinates(tmp_path / "m.npz", coords), exemplar_size=(48, 40))


@needs_exr
def test_a_failed_exr_write_leaves_nothing_and_keeps_the_old_file(tmp_path, monkeypatch):
    import OpenEXR

    from texsynth.io import _formats

    old = save_image(tmp_path / "h.exr", np.full((4, 4), 0.25))

    class Failing:  # OpenEXR as it behaves on a full disk: part of the file written, then a RuntimeError
        ZIP_COMPRESSION, scanlineimage = OpenEXR.ZIP_COMPRESSION, OpenEXR.scanlineimage

        class File:
            def __init__(self, header, channels):
                pass

            def write(self, name):
                Path(name).write_bytes(b"v/1\x01 partial")
                raise RuntimeError("No space left on device")

    monkeypatch.setattr(_formats, "openexr", lambda: Failing)
    with pytest.raises(OSError, match="No space left"):
        save_image(old, np.full((4, 4), 0.75), overwrite=True)
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.exr"]
    assert np.array_equal(load_image(old), np.full((4, 4), 0.25, np.float32))


def test_a_folder_of_exr_frames_is_read_in_name_order(tmp_path):
    frames = np.stack([np.full((4, 5, 3), v) for v in (0.25, 0.5, 0.75)])
    (tmp_path / "seq").mkdir()
    for i, frame in enumerate(frames):
        save_image(tmp_path / "seq" / f"f{i:02d}.exr", frame, bits=32)
    np.testing.assert_array_equal(load_frames(tmp_path / "seq"), frames)
