"""Tests of texsynth.core.flows: flow fields and backward warping."""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from texsynth.core.flows import flow_sequence, rotation, sink, source, translation, vortex, warp, warp_coordinates
from texsynth.io import load_image

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


@pytest.fixture(scope="module")
def metal():
    if not TEXTURES.is_dir():
        pytest.skip("../shared/textures is not available")
    return load_image(TEXTURES / "lcv" / "metal.pgm")[:64, :64]


@settings(max_examples=20, deadline=None)
@given(dy=st.integers(-5, 5), dx=st.integers(-5, 5))
def test_integer_translation_with_wrap_is_a_roll(dy, dx):
    img = np.random.default_rng(0).random((12, 10, 2))
    out = warp(img, translation((12, 10), (dy, dx)), mode="wrap")
    np.testing.assert_allclose(out, np.roll(img, (dy, dx), axis=(0, 1)), atol=1e-12)


def test_rotation_moves_a_blob_along_the_circle():
    h = w = 65
    y, x = np.mgrid[:h, :w]
    blob = np.exp(-((y - 32) ** 2 + (x - 52) ** 2) / 8.0)  # 20 px right of the centre
    # counter-clockwise on screen by 30 degrees: up and to the left. The flow's
    # inversion contracts by |R - I| = 2 sin(15 deg) = 0.52 per iteration: use 12.
    out = warp(blob, rotation((h, w), np.pi / 6), iterations=12)
    cy, cx = (np.array([(out * y).sum(), (out * x).sum()]) / out.sum())
    np.testing.assert_allclose([cy, cx], [32 - 20 * np.sin(np.pi / 6), 32 + 20 * np.cos(np.pi / 6)], atol=0.15)
    # a small per-frame angle needs only the default iterations
    out = warp(blob, rotation((h, w), 0.1))
    cy, cx = (np.array([(out * y).sum(), (out * x).sum()]) / out.sum())
    np.testing.assert_allclose([cy, cx], [32 - 20 * np.sin(0.1), 32 + 20 * np.cos(0.1)], atol=0.15)


def test_fixed_point_inversion_beats_plain_semi_lagrangian():
    h = w = 65
    y, x = np.mgrid[:h, :w]
    blob = np.exp(-((y - 32) ** 2 + (x - 60) ** 2) / 8.0)
    flow = rotation((h, w), 0.4)
    target = np.array([32 - 28 * np.sin(0.4), 32 + 28 * np.cos(0.4)])

    def centroid(img):
        return np.array([(img * y).sum(), (img * x).sum()]) / img.sum()

    err_one = np.linalg.norm(centroid(warp(blob, flow, iterations=1)) - target)
    err_fp = np.linalg.norm(centroid(warp(blob, flow, iterations=4)) - target)
    assert err_fp < 0.3 * err_one


def test_warp_keeps_layout_and_marks_holes(metal):
    out, valid = warp(metal, rotation(metal.shape, 0.3), return_valid=True)
    assert out.shape == metal.shape and valid.shape == metal.shape
    assert valid[32, 32] and not valid[0, 0]  # corners come from outside the frame
    # constant mode fills holes with cval (0); pixels less than 1 px outside blend with it
    assert out[~valid].mean() < 0.3 * metal.mean()
    colour = np.stack([metal] * 3, -1).astype(np.float32)
    assert warp(colour, translation(metal.shape, (1.5, -2.0))).dtype == np.float32
    _, valid = warp(metal, rotation(metal.shape, 0.3), mode="wrap", return_valid=True)
    assert valid.all()


def test_zero_flow_is_identity(metal):
    np.testing.assert_allclose(warp(metal, np.zeros(metal.shape + (2,))), metal, atol=1e-12)


def test_radial_and_vortex_flows():
    s, o = sink((21, 21), 2.0), source((21, 21), 2.0)
    np.testing.assert_allclose(s[10, 0], [0.0, 2.0])  # left of the centre moves right, inwards
    np.testing.assert_allclose(o[10, 0], [0.0, -2.0])
    assert np.all(np.hypot(*np.moveaxis(s, -1, 0)) <= 2.0 + 1e-12)
    # divergence: negative for a sink, positive for a source
    div = lambda f: np.gradient(f[..., 0], axis=0) + np.gradient(f[..., 1], axis=1)  # noqa: E731
    assert div(s)[5:16, 5:16].mean() < 0 < div(o)[5:16, 5:16].mean()
    v = vortex((41, 41), 1.5, radius=5.0)
    speed = np.hypot(*np.moveaxis(v, -1, 0))
    assert speed.max() == pytest.approx(1.5)
    # tangential: perpendicular to the radius everywhere
    y, x = np.mgrid[:41, :41] - 20.0
    np.testing.assert_allclose(v[..., 0] * y + v[..., 1] * x, 0.0, atol=1e-12)
    # the vortex is divergence-free (up to finite differences at the core's kink)
    assert abs(div(v)[5:36, 5:36]).mean() < 0.05 * abs(div(s)[5:36, 5:36]).mean()


def test_flow_sequence_forms_and_errors():
    f = translation((8, 9), (1.0, 0.0))
    assert flow_sequence(f, 4).shape == (3, 8, 9, 2)
    seq = flow_sequence(lambda i: translation((8, 9), (i, 0.0)), n_frames=3)
    assert seq[1, 0, 0, 0] == 1.0
    assert flow_sequence(np.zeros((2, 8, 9, 2))).shape == (2, 8, 9, 2)
    with pytest.raises(ValueError, match="frames"):
        flow_sequence(f)
    with pytest.raises(ValueError, match="frames"):
        flow_sequence(lambda i: f)
    with pytest.raises(ValueError, match="flows"):
        flow_sequence(np.zeros((2, 8, 9, 3)))
    with pytest.raises(ValueError, match="frames"):
        flow_sequence(np.zeros((2, 8, 9, 2)), n_frames=5)
    with pytest.raises(ValueError, match="flows\\(1\\)"):
        flow_sequence(lambda i: np.zeros((8, 9, 2)) if i == 0 else np.zeros((8, 8, 2)), n_frames=3)


def test_bad_warp_input(metal):
    with pytest.raises(ValueError, match="flow"):
        warp(metal, np.zeros((10, 10, 2)))
    bad = np.zeros(metal.shape + (2,))
    bad[0, 0, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        warp(metal, bad)
    with pytest.raises(ValueError, match="mode"):
        warp(metal, np.zeros(metal.shape + (2,)), mode="mirror")
    with pytest.raises(TypeError, match=r"mode must be one of 'constant', .*, got list"):
        warp(metal, np.zeros(metal.shape + (2,)), mode=["wrap"])
    with pytest.raises(TypeError, match="mode must be one of"):
        warp(metal, np.zeros(metal.shape + (2,)), mode=np.array(["wrap", "reflect"]))
    with pytest.raises(ValueError, match=r"velocity must be a pair \(d_row, d_col\), got array"):
        translation((4, 4), np.zeros(3))
    with pytest.raises(ValueError, match="radius"):
        vortex((8, 8), 1.0, radius=0.0)
    with pytest.raises(ValueError, match="speed"):
        sink((8, 8), -1.0)


# --------------------------------------------------------------------------- correspondence warp
def _copy_field(h, w, offsets):
    """Correspondence of an image pasted from a few copies: left half from offsets[0], right from [1]."""
    rows, cols = np.meshgrid(np.arange(h, dtype=float), np.arange(w, dtype=float), indexing="ij")
    grid = np.stack([rows, cols], axis=-1)
    off = np.where((cols < w // 2)[..., None], np.array(offsets[0], float), np.array(offsets[1], float))
    return grid + off, grid


@settings(max_examples=25, deadline=None)
@given(dy=st.floats(-3, 3), dx=st.floats(-3, 3))
def test_warp_coordinates_moves_a_copy_exactly(dy, dx):
    # inside one copy the correspondence is a translation: carrying it along any
    # (sub-pixel) translation must give exactly "source position + offset", not a
    # rounded or interpolated one
    coords, grid = _copy_field(16, 20, [(30.0, 40.0), (30.0, 40.0)])
    out, valid = warp_coordinates(coords, translation((16, 20), (dy, dx)), return_valid=True)
    want = grid - [dy, dx] + [30.0, 40.0]
    np.testing.assert_allclose(out[valid], want[valid], atol=1e-9)
    assert valid[4:12, 4:16].all()


def test_warp_coordinates_never_averages_across_a_seam():
    # two unrelated copies side by side: every warped position must belong to one of
    # them (offset 0 -> (30, 40) or (70, 5)); warping the field like an image
    # (bilinear) invents positions between the two copies at the seam
    coords, grid = _copy_field(12, 16, [(30.0, 40.0), (70.0, 5.0)])
    flow = translation((12, 16), (0.0, 0.5))
    src = grid - [0.0, 0.5]
    offset = warp_coordinates(coords, flow) - src
    is_a = np.all(np.abs(offset - [30.0, 40.0]) < 1e-9, axis=-1)
    is_b = np.all(np.abs(offset - [70.0, 5.0]) < 1e-9, axis=-1)
    assert np.all(is_a | is_b)
    blurred = np.stack([warp(coords[..., k] / 100.0, flow, mode="nearest") * 100.0 for k in range(2)], -1) - src
    near_a = np.all(np.abs(blurred - [30.0, 40.0]) < 1e-6, axis=-1)
    near_b = np.all(np.abs(blurred - [70.0, 5.0]) < 1e-6, axis=-1)
    assert not np.all(near_a | near_b)  # the colour warp does mix them: the test can tell


def test_bad_warp_coordinates_input():
    with pytest.raises(ValueError, match="coords"):
        warp_coordinates(np.zeros((4, 4)), translation((4, 4), (0, 1)))
    with pytest.raises(ValueError, match="flow"):
        warp_coordinates(np.zeros((4, 4, 2)), translation((4, 5), (0, 1)))
    with pytest.raises(ValueError, match="mode"):
        warp_coordinates(np.zeros((4, 4, 2)), translation((4, 4), (0, 1)), mode="mirror")
    with pytest.raises(TypeError, match="mode must be one of"):
        warp_coordinates(np.zeros((4, 4, 2)), translation((4, 4), (0, 1)), mode=["wrap"])
