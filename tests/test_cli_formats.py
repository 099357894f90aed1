"""File formats on the command line (issue 34): channel outputs in their own format and depth, float data
outside [0, 1] restored on output, EXR and TGA, coordinate maps as images for a shader."""

import importlib.util
import sys

import numpy as np
import pytest

import texsynth
from texsynth import cli, data
from texsynth.io import image_bits, load_coordinates, load_image, normalize_range, restore_range, save_image

needs_exr = pytest.mark.skipif(importlib.util.find_spec("OpenEXR") is None,
                               reason="the exr extra (OpenEXR) is not installed")


def run(*argv):
    return cli.main([str(a) for a in argv])


def _material(tmp_path):
    """A bread albedo (8-bit PNG), its height in metres (float32 TIFF, [-0.02, 0.05]), a roughness (16-bit PNG)."""
    albedo = data.load("bread")[:40, :40]
    grey = albedo.mean(-1)
    grey = (grey - grey.min()) / (grey.max() - grey.min())
    height = (grey * 0.07 - 0.02).astype(np.float32)
    rough = (grey[::-1] * 65535).astype(np.uint16)
    return (albedo, height, rough, save_image(tmp_path / "albedo.png", albedo),
            save_image(tmp_path / "height.tif", height, bits=32), save_image(tmp_path / "rough.png", rough, bits=16))


def test_each_channel_keeps_its_own_format_depth_and_values(tmp_path, capsys):
    albedo, height, rough, a, h, r = _material(tmp_path)
    argv = ["quilt", a, "-o", tmp_path / "out.png", "--size", "56x48", "--seed", "0", "--block", "16",
            "--channels", f"{h},{r}", "--no-progress"]
    assert run(*argv) == 0
    out, info = texsynth.quilt(albedo, (48, 56), block=16, rng=0, return_info=True)
    # the float32 TIFF height comes back as a float32 TIFF, in metres (not a 16-bit PNG scaled to [0, 1])
    assert image_bits(tmp_path / "out_height.tif") == 32 and not (tmp_path / "out_height.png").exists()
    import tifffile

    back = tifffile.imread(tmp_path / "out_height.tif")
    assert back.dtype == np.float32
    assert np.allclose(back, texsynth.apply_coordinates(height, info), rtol=0, atol=1e-7)
    assert back.min() < 0  # the range survived: below zero, as the input
    # the 16-bit PNG stays a 16-bit PNG
    assert image_bits(tmp_path / "out_rough.png") == 16
    assert np.array_equal(load_image(tmp_path / "out_rough.png"), texsynth.apply_coordinates(rough, info) / 65535)
    # --channel-format output: the output's suffix (the old rule); the height is kept scaled, with a note
    capsys.readouterr()
    assert run(*argv, "--channel-format", "output", "-o", tmp_path / "o2.png") == 0
    err = capsys.readouterr().err
    assert image_bits(tmp_path / "o2_height.png") == 16 and "0 is -0.02" in err and "1 is 0.05" in err
    unit = load_image(tmp_path / "o2_height.png")
    assert np.abs(restore_range(unit, (float(height.min()), float(height.max())))
                  - texsynth.apply_coordinates(height, info)).max() < 0.07 / 65535 + 1e-7
    # a forced format
    assert run(*argv, "--channel-format", "tif32", "-o", tmp_path / "o3.png") == 0
    assert image_bits(tmp_path / "o3_rough.tif") == 32 and image_bits(tmp_path / "o3_height.tif") == 32
    with pytest.raises(SystemExit):
        run(*argv, "--channel-format", "webp")


def test_float_input_outside_the_unit_range_is_synthesised_and_restored(tmp_path, capsys):
    grey = data.load("bread")[:40, :40].mean(-1)
    heights = ((grey - grey.min()) / (grey.max() - grey.min()) * 7 - 2).astype(np.float32)  # [-2, 5]
    source = save_image(tmp_path / "h.tif", heights, bits=32)
    assert run("quilt", source, "-o", tmp_path / "q.tif", "--size", "48x48", "--seed", "1", "--block", "16") == 0
    unit, value_range = normalize_range(heights)
    expected = restore_range(texsynth.quilt(unit, 48, block=16, rng=1), value_range)
    import tifffile

    back = tifffile.imread(tmp_path / "q.tif")
    assert back.dtype == np.float32 and np.array_equal(back, expected)
    assert back.min() >= heights.min() and back.max() <= heights.max() and back.min() < 0
    # a 16-bit PNG output keeps the scaled values, and says what 0 and 1 stand for
    capsys.readouterr()
    assert run("quilt", source, "-o", tmp_path / "q.png", "--size", "48x48", "--seed", "1", "--block", "16") == 0
    assert "0 is -2, 1 is 5" in capsys.readouterr().err
    assert np.abs(load_image(tmp_path / "q.png") - texsynth.quilt(unit, 48, block=16, rng=1)).max() <= 0.5 / 65535 + 1e-6


def test_several_inputs_outside_the_unit_range_share_one_range(tmp_path):
    a = (data.load("bread")[:24, :24].mean(-1) * 3).astype(np.float32)  # [0, 3]
    b = (data.load("wood")[:24, :24].mean(-1) - 1).astype(np.float32)  # [-1, 0]
    files = [save_image(tmp_path / "a.tif", a, bits=32), save_image(tmp_path / "b.tif", b, bits=32)]
    assert run("mix-textures", *files, "-o", tmp_path / "m.tif", "--size", "24x20", "--seed", "0", "--levels", "1",
               "--weights", "ramp", "--bits", "32") == 0
    import tifffile

    back = tifffile.imread(tmp_path / "m.tif")
    joint = (min(a.min(), b.min()), max(a.max(), b.max()))
    assert joint[0] <= back.min() and back.max() <= joint[1]
    assert back[:, 0].mean() < 0 < back[:, -1].mean() or back[:, -1].mean() < 0 < back[:, 0].mean()


@needs_exr
def test_exr_in_and_out_on_the_command_line(tmp_path):
    albedo = data.load("bread")[:40, :40]
    hdr = (albedo * 12).astype(np.float32)  # HDR colour up to 12
    source = save_image(tmp_path / "hdr.exr", hdr)
    normal = np.dstack([np.zeros((40, 40, 2)), np.ones((40, 40))]).astype(np.float32)  # unit vectors in [-1, 1]
    normal[:, 20:, 0], normal[:, 20:, 2] = 0.6, 0.8
    n_file = save_image(tmp_path / "normal.exr", normal)
    assert run("quilt", source, "-o", tmp_path / "q.exr", "--size", "48x48", "--seed", "0", "--block", "16",
               "--normal-maps", n_file) == 0
    back = load_image(tmp_path / "q.exr", normalize=True)
    assert image_bits(tmp_path / "q.exr") == 32 and back[1][1] > 1  # HDR values kept
    _, info = texsynth.quilt(normalize_range(hdr)[0], 48, block=16, rng=0, return_info=True)
    assert np.allclose(restore_range(*back), texsynth.apply_coordinates(hdr, info), rtol=1e-6, atol=1e-6)
    rendered = restore_range(*load_image(tmp_path / "q_normal.exr", normalize=True))
    assert np.allclose(np.linalg.norm(rendered, axis=-1), 1, atol=1e-5)  # still unit vectors in [-1, 1]
    assert run("quilt", source, "-o", tmp_path / "h.exr", "--size", "48x48", "--bits", "16") == 0
    assert image_bits(tmp_path / "h.exr") == 16
    assert run("quilt", source, "-o", tmp_path / "b.exr", "--bits", "8") == 2 and not (tmp_path / "b.exr").exists()


def test_exr_without_the_extra_is_refused_before_the_synthesis(tmp_path, monkeypatch, capsys):
    source = save_image(tmp_path / "a.png", data.load("bread")[:32, :32])
    import functools

    import texsynth.patch

    monkeypatch.setitem(sys.modules, "OpenEXR", None)
    called = []
    real = texsynth.patch.quilt

    @functools.wraps(real)
    def spy(*args, **kwargs):
        called.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(texsynth.patch, "quilt", spy)
    assert run("quilt", source, "-o", tmp_path / "q.exr") == 2
    assert "pip install 'OpenEXR" in capsys.readouterr().err and not called and not (tmp_path / "q.exr").exists()


def test_tga_in_and_out(tmp_path):
    rgba = np.dstack([data.load("bread")[:32, :32], np.ones((32, 32))])
    source = save_image(tmp_path / "a.tga", rgba)
    assert run("quilt", source, "-o", tmp_path / "q.tga", "--size", "40x40", "--block", "16", "--seed", "0") == 0
    assert load_image(tmp_path / "q.tga").shape == (40, 40, 4)


@pytest.mark.parametrize("suffix", [".png", ".tif", pytest.param(".exr", marks=needs_exr)])
def test_coordinate_map_images_are_written_and_applied_later(tmp_path, suffix, capsys):
    albedo, height, rough, a, h, r = _material(tmp_path)
    the_map = tmp_path / f"map{suffix}"
    assert run("quilt", a, "-o", tmp_path / "out.png", "--size", "56x48", "--seed", "0", "--block", "16",
               "--channels", h, "--coordinates", the_map) == 0
    _, info = texsynth.quilt(albedo, (48, 56), block=16, rng=0, return_info=True)
    assert np.array_equal(load_coordinates(the_map).coordinates, info.coordinates)
    rgb = load_image(the_map)
    assert rgb.shape == (48, 56, 3) and np.all((rgb[..., :2] > 0) & (rgb[..., :2] < 1))
    assert run("apply-coordinates", the_map, h, "-o", tmp_path / "later.tif") == 0
    assert np.array_equal(load_image(tmp_path / "later.tif", normalize=True)[0],
                          load_image(tmp_path / "out_height.tif", normalize=True)[0])
    # a channel of another size than the exemplar the map records is refused
    save_image(tmp_path / "small.png", albedo[:30])
    capsys.readouterr()
    assert run("apply-coordinates", the_map, tmp_path / "small.png", "-o", tmp_path / "x.png") == 2
    assert "40x40" in capsys.readouterr().err and not (tmp_path / "x.png").exists()


def test_a_map_image_from_another_program_is_read_at_the_channel_size(tmp_path):
    albedo, height, rough, a, h, r = _material(tmp_path)
    assert run("quilt", a, "-o", tmp_path / "out.png", "--size", "48x48", "--seed", "0", "--block", "16",
               "--channels", r, "--coordinates", tmp_path / "map.png") == 0
    plain = save_image(tmp_path / "plain.png", load_image(tmp_path / "map.png"), bits=16)  # no note of the size
    assert run("apply-coordinates", plain, r, "-o", tmp_path / "again.png") == 0
    assert np.array_equal(load_image(tmp_path / "again.png"), load_image(tmp_path / "out_rough.png"))


def test_map_images_that_cannot_hold_the_map_are_refused_up_front(tmp_path, capsys):
    a, b = (save_image(tmp_path / f"{n}.png", data.load(n)[:24, :24]) for n in ("bread", "wood"))
    assert run("mix-textures", a, b, "-o", tmp_path / "m.png", "--size", "24x20", "--coordinates",
               tmp_path / "m_map.png") == 2
    assert "several inputs" in capsys.readouterr().err and not (tmp_path / "m.png").exists()
    assert run("quilt", a, "-o", tmp_path / "q.png", "--coordinates", tmp_path / "q.jpg") == 2
    assert ".npz" in capsys.readouterr().err and not (tmp_path / "q.png").exists()
