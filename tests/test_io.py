"""Image and frame I/O: round trips, bit depths, atomic and non-overwriting saves."""

import numpy as np
import pytest

from texsynth import data
from texsynth.io import load_frames, load_image, save_frames, save_image, to_uint


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


def test_to_uint_rounds_and_clips():
    assert to_uint(np.array([-0.1, 0.5, 1.2])).tolist() == [0, 128, 255]
    assert to_uint(np.array([1.0]), 16).tolist() == [65535]
    with pytest.raises(ValueError, match="bits"):
        to_uint(np.zeros(2), 12)


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
