"""The front door: texsynth.synthesize analyses an exemplar and runs the method that suits it."""

import numpy as np
import pytest
from scipy import ndimage

import texsynth
from texsynth import data
from texsynth._synthesize import COURSES, DIRECTIONAL, GRAIN, LARGE_ELEMENTS, METHODS, RULES

FAST = dict(rng=0)


def _bricks(shape=(128, 128), course=16, brick=40, mortar=3, seed=0):
    """A running-bond brick wall: courses every ``course`` rows, joints shifted by half a brick per course."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[:shape[0], :shape[1]]
    shift = (rows // course) % 2 * (brick // 2)
    wall = ((rows % course) >= mortar) & (((cols + shift) % brick) >= mortar)
    return np.clip(0.3 + 0.4 * wall + 0.05 * rng.standard_normal(shape), 0, 1)


def _oriented_noise(angle_degrees, shape=(128, 128), seed=0):
    """Noise smeared along one direction (grain, roots): no period, one dominant orientation."""
    noise = np.random.default_rng(seed).random(shape)
    smeared = ndimage.gaussian_filter(noise, (12, 1))  # long along the rows' axis: vertical streaks
    turned = ndimage.rotate(smeared, angle_degrees - 90, reshape=False, mode="wrap")
    return (turned - turned.min()) / np.ptp(turned)


def _blobs(shape=(128, 128), seed=0, sigma=2):
    noise = ndimage.gaussian_filter(np.random.default_rng(seed).random(shape), sigma, mode="wrap")
    return (noise - noise.min()) / np.ptp(noise)


def test_the_analysis_tells_regular_directional_and_stochastic_apart():
    bricks = texsynth.analyze_exemplar(_bricks())
    assert bricks.kind == "regular" and max(s for _, s in bricks.courses) >= COURSES
    assert bricks.courses[0][0] == 16  # the courses' period down the rows, in pixels
    vertical = texsynth.analyze_exemplar(_oriented_noise(90))
    assert vertical.kind == "directional" and vertical.anisotropy >= DIRECTIONAL
    assert abs(vertical.orientation - 90) < 10  # roots that run down the image: 90 degrees
    diagonal = texsynth.analyze_exemplar(_oriented_noise(45))
    assert diagonal.kind == "directional" and abs(diagonal.orientation - 45) < 10
    blobs = texsynth.analyze_exemplar(_blobs())
    assert blobs.kind == "stochastic" and blobs.anisotropy < DIRECTIONAL
    larger = np.clip(ndimage.zoom(_blobs((64, 64)), 2), 0, 1)  # the same blobs, twice the size
    assert texsynth.analyze_exemplar(larger).element_size > 1.5 * blobs.element_size


@pytest.mark.parametrize("preset", ["quilt", "patch_sampling", "patchwork", "graphcut-texture"])
def test_a_named_preset_is_that_method_with_its_defaults(preset):
    exemplar = data.load("bread")[:64, :64]
    out, info = texsynth.synthesize(exemplar, 80, preset=preset, return_info=True, **FAST)
    name = preset.replace("-", "_")
    assert info.method == name and info.analysis is None
    assert np.array_equal(out, getattr(texsynth, name)(exemplar, (80, 80), **FAST))


@pytest.mark.parametrize("make", [_bricks, lambda: _oriented_noise(90), _blobs])
def test_auto_runs_the_method_its_rules_choose_and_says_why(make):
    exemplar = make()
    out, info = texsynth.synthesize(exemplar, 160, return_info=True, **FAST)
    analysis = texsynth.analyze_exemplar(exemplar)
    method, options, reason = texsynth.choose_method(analysis)
    expected = next(chosen for _, test, chosen, _ in RULES if test(analysis))  # the first rule that holds
    assert (info.method, info.options) == (method, options) and method == expected
    assert np.array_equal(out, getattr(texsynth, method)(exemplar, (160, 160), **options, **FAST))
    assert info.choice == reason and f"the exemplar is {analysis.kind}" in reason
    assert info.seconds >= info.analysis.seconds > 0


def test_a_grid_of_lines_gets_whole_cells_on_it():
    tiles = np.full((128, 128), 0.6)
    tiles[::32, :] = tiles[:, ::32] = 0.1  # dark grout every 32 px along both axes
    tiles = np.clip(tiles + 0.05 * np.random.default_rng(0).standard_normal(tiles.shape), 0, 1)
    analysis = texsynth.analyze_exemplar(tiles)
    method, options, reason = texsynth.choose_method(analysis)
    assert analysis.kind == "regular" and analysis.grid is not None and abs(analysis.grid[0] - 32) < 1
    assert method == "near_regular_texture" and options == {"lattice": analysis.grid} and "grid" in reason


def test_grain_and_large_elements_get_graph_cuts_and_the_rest_texture_optimization():
    grain = texsynth.analyze_exemplar(_oriented_noise(90))
    assert grain.anisotropy >= GRAIN and texsynth.choose_method(grain)[0] == "graphcut_texture"
    large = texsynth.analyze_exemplar(_blobs(sigma=16))  # blobs 60-90 px across
    assert large.element_size >= LARGE_ELEMENTS > texsynth.analyze_exemplar(_blobs()).element_size
    method, _, reason = texsynth.choose_method(large)
    assert method == "graphcut_texture" and "elements this large" in reason
    rows, cols = np.mgrid[:128, :128]
    weave = 0.5 + 0.25 * np.sin(2 * np.pi * rows / 16) * np.sin(2 * np.pi * cols / 16)  # regular, no lines
    analysis = texsynth.analyze_exemplar(weave)
    assert analysis.kind == "regular" and analysis.grid is None
    assert texsynth.choose_method(analysis)[:2] == ("optimize_texture", {})
    assert texsynth.choose_method(texsynth.analyze_exemplar(_blobs()))[0] == "optimize_texture"


def test_fast_and_quality_presets_and_tileable_pass_through():
    exemplar = data.load("bread")[:64, :64]
    assert texsynth.synthesize(exemplar, 64, preset="fast", return_info=True, **FAST)[1].method == \
        "patch_sampling"
    assert texsynth.synthesize(exemplar, 64, preset="quality", return_info=True, **FAST)[1].method == \
        "graphcut_texture"
    tiled = texsynth.synthesize(exemplar, 96, preset="quilt", tileable=True, **FAST)
    assert np.array_equal(tiled, texsynth.quilt(exemplar, 96, tileable=True, **FAST))


def test_the_info_renders_the_other_channels_like_the_chosen_methods():
    albedo = data.load("bread")[:64, :64]
    height = albedo.mean(-1)
    out, info = texsynth.synthesize(albedo, 96, return_info=True, **FAST)
    via_front, via_method = texsynth.apply_coordinates([height], info), \
        texsynth.apply_coordinates([height], info.method_info)
    assert np.array_equal(via_front[0], via_method[0]) and via_front[0].shape == (96, 96)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(preset="best"), ValueError, "preset"),
    (dict(preset=3), TypeError, "preset"),
    (dict(size=0), ValueError, "size"),
    (dict(tileable="yes"), TypeError, "tileable"),
])
def test_bad_input_names_the_parameter(kwargs, error, match):
    args = {"size": 64, **kwargs}
    with pytest.raises(error, match=match):
        texsynth.synthesize(data.load("bread")[:64, :64], **args)


def test_every_method_the_front_door_names_is_public():
    assert all(callable(getattr(texsynth, m)) for m in METHODS)
    assert {method for _, _, method, _ in RULES} <= set(METHODS) and RULES[-1][0] == "otherwise"


def test_the_command(tmp_path, capsys):
    from texsynth.cli import main
    from texsynth.io import load_image, save_image

    src = save_image(tmp_path / "brick.png", data.load("brick"))
    assert main(["synthesize", str(src), "-o", str(tmp_path / "out.png"), "--size", "2x", "-s", "0",
                 "--no-progress"]) == 0, capsys.readouterr().err
    out = load_image(tmp_path / "out.png")
    assert out.shape[:2] == (2 * data.load("brick").shape[0], 2 * data.load("brick").shape[1])
    assert main(["synthesize", str(src), "-o", str(tmp_path / "q.png"), "--preset", "best", "--no-progress"]) == 2
    assert "preset" in capsys.readouterr().err
