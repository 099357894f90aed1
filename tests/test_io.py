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
    import texsynth.io as tio

    save_frames(tmp_path / "seq", np.ones((2, 4, 4)))
    calls = []

    def failing_imwrite(target, *args, **kwargs):
        calls.append(target)
        if len(calls) == 2:
            raise OSError("disk full")
        return real(target, *args, **kwargs)

    real = tio.iio.imwrite
    monkeypatch.setattr(tio.iio, "imwrite", failing_imwrite)
    with pytest.raises(OSError, match="disk full"):
        save_frames(tmp_path / "seq", np.zeros((3, 4, 4)), overwrite=True)
    monkeypatch.undo()
    assert load_frames(tmp_path / "seq").min() == 1.0  # the old frames are untouched
    assert [p.name for p in tmp_path.iterdir()] == ["seq"]  # no temporary folder left


def test_video_without_the_extra_says_how_to_get_it(tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None if name == "imageio_ffmpeg" else real(name))
    with pytest.raises(ValueError, match=r"texsynth\[video\]"):
        save_frames(tmp_path / "v.mp4", np.zeros((3, 8, 8)))
    assert list(tmp_path.iterdir()) == []


def test_mp4_round_trip(tmp_path):
    pytest.importorskip("imageio_ffmpeg")  # in the test extra, so CI runs this
    frames = np.stack([np.roll(data.load("bumpy")[:32, :32], 2 * t, axis=1) for t in range(6)])
    back = load_frames(save_frames(tmp_path / "v.mp4", frames, fps=6))
    assert back.shape == (6, 32, 32, 3)
    assert np.abs(back - frames).mean() < 0.1  # lossy codec: colours close, not exact
