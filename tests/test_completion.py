"""Image completion (texsynth.inpaint, texsynth.uncrop) and the hard constraints they stand on."""

from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

import texsynth
from texsynth.io import load_image
from texsynth import optimize_texture
from texsynth.optimization import Constraints, Schedule


PHOTOS = Path(__file__).resolve().parents[1] / "benchmarks" / "photos"


def sharpness(img, where):
    """Mean absolute difference of 4-neighbours inside ``where``."""
    dx = np.abs(np.diff(img, axis=1)).mean(-1)[where[:, 1:] & where[:, :-1]]
    dy = np.abs(np.diff(img, axis=0)).mean(-1)[where[1:] & where[:-1]]
    return (dx.mean() + dy.mean()) / 2


def disc(shape, centre, radius):
    rows, cols = np.mgrid[: shape[0], : shape[1]]
    return (rows - centre[0]) ** 2 + (cols - centre[1]) ** 2 < radius**2


@pytest.fixture(scope="module")
def bricks():
    """A red brick wall, colour (a photograph committed with the benchmarks)."""
    photo = load_image(Path(__file__).resolve().parents[1] / "benchmarks" / "photos" / "bricks_1.png")
    return np.ascontiguousarray(photo[:160, :160, :3]).astype(np.float32)


def test_hard_constraints_keep_the_targets_exactly(texture):
    ex = texture("jcjohnson/bread.png", 48)
    mask = np.zeros((48, 48), bool)
    mask[:, :20] = True
    schedule = Schedule(neighborhood_sizes=(16, 8), levels=2, max_iterations=2)
    out = optimize_texture(ex, 48, constraints=Constraints(mask=mask, target=ex, constraint_weight=float("inf")),
                           schedule=schedule, rng=0)
    np.testing.assert_array_equal(out[mask], ex[mask])
    soft = optimize_texture(ex, 48, constraints=Constraints(mask=mask, target=ex, constraint_weight=100.0),
                            schedule=schedule, rng=0)
    assert 0 < np.abs(soft[mask] - ex[mask]).max()  # the soft constraint only pulls


def test_inpaint_fills_the_hole_with_sharp_texture_and_keeps_the_rest(bricks):
    hole = disc(bricks.shape[:2], (80, 84), 26)
    out, info = texsynth.inpaint(bricks, hole, rng=0, return_info=True)
    np.testing.assert_array_equal(out[~hole], bricks[~hole])  # bit for bit outside the hole
    core = disc(bricks.shape[:2], (80, 84), 20)
    # A fill that averages disagreeing neighbourhoods is blurred: a Gaussian blur of sigma 1 px keeps
    # 0.45 of the known pixels' sharpness on this wall; the filled interior measured 0.93 (seed 0).
    assert sharpness(out, core) / sharpness(bricks, ~hole) > 0.7
    # Its colours are the wall's: the mean within 0.05 of the known pixels' (mortar and brick differ by 0.3).
    assert np.abs(out[core].mean(0) - bricks[~hole].mean(0)).max() < 0.05
    assert info.seconds > 0


def test_a_last_stage_of_small_neighbourhoods_joins_the_fill_to_the_known_pixels():
    # "auto" sizes go on halving down to 8 px (the default preset's stop at 16 for 64). The seam is
    # the mean |difference| across the hole's boundary over that between known neighbours (1: as
    # smooth as the texture). Measured on 256 px crops, a disc of radius 40, seeds 0-3 (2026-11-24,
    # the neighbourhoods away from the hole left out): with the 8-px stage 1.45, 1.59, 1.41, 1.47
    # (pebbles), 1.88, 2.16, 1.97, 2.02 (bark); without it 1.40, 1.92, 1.65, 1.48 and 2.72, 2.58,
    # 2.94, 2.70. One fill's seam varies by 0.1-0.3 with the seed, so the test pools two photos and
    # two seeds: their sums' ratio was 0.82 (0.76 with the whole image searched); a stage that
    # changed nothing would give 1, and 0.9 lies between.
    hole = disc((256, 256), (128, 128), 40)

    def seam(img):
        dx, dy = np.abs(np.diff(img, axis=1)).mean(-1), np.abs(np.diff(img, axis=0)).mean(-1)
        cross = np.concatenate([dx[hole[:, 1:] != hole[:, :-1]], dy[hole[1:] != hole[:-1]]])
        return cross.mean() / sharpness(img, ~hole)

    with_8 = without = 0.0
    for photo in ("pebbles_1", "bark_1"):
        image = load_image(PHOTOS / f"{photo}.png")[:256, :256, :3].astype(np.float32)
        for seed in (0, 1):
            # the fills as the synthesis makes them (blend_width=0): the blend below would hide the difference
            out, info = texsynth.inpaint(image, hole, rng=seed, blend_width=0, return_info=True)
            sizes = sorted({stage.size for stage in info.stages}, reverse=True)
            assert sizes[-1] == 8 and len(sizes) > 3  # a coarse-featured photo: 64, 32, 16 and then 8
            with_8 += seam(out)
            without += seam(texsynth.inpaint(image, hole, rng=seed, blend_width=0,
                                             neighborhood_sizes=tuple(sizes[:-1])))
    assert with_8 < 0.9 * without


def test_the_fill_is_blended_into_the_image_in_the_gradient_domain():
    # By default the filled pixels within 32 px of the known ones are blended into them (a membrane that takes
    # away the fill's colour offset from the image, smoothed along the border): the step in colour where the
    # fill meets the image goes, its texture stays. Measured on the 256 px crops, a disc of radius 40, seeds
    # 0-1: seams 0.80, 0.85 (pebbles) and 1.43, 1.67 (bark) against 1.45, 1.59 and 1.88, 2.16 without (1: as
    # smooth as the texture); sharpness of the fill 0.77-1.02 of the image's, within 0.005 of the unblended's.
    hole = disc((256, 256), (128, 128), 40)
    far = hole & (ndimage.distance_transform_edt(hole) > 32)

    def seam(img):
        dx, dy = np.abs(np.diff(img, axis=1)).mean(-1), np.abs(np.diff(img, axis=0)).mean(-1)
        cross = np.concatenate([dx[hole[:, 1:] != hole[:, :-1]], dy[hole[1:] != hole[:-1]]])
        return cross.mean() / sharpness(img, ~hole)

    for photo in ("pebbles_1", "bark_1"):
        image = load_image(PHOTOS / f"{photo}.png")[:256, :256, :3].astype(np.float32)
        blended = texsynth.inpaint(image, hole, rng=0)
        raw = texsynth.inpaint(image, hole, rng=0, blend_width=0)
        np.testing.assert_array_equal(blended[~hole], image[~hole])  # the image, bit for bit
        np.testing.assert_array_equal(blended[far], raw[far])        # the fill beyond the band, as synthesised
        # a ratio of 1 would mean no effect; measured 0.53-0.55 (pebbles) and 0.76-0.78 (bark)
        assert seam(blended) < 0.85 * seam(raw)
        assert sharpness(blended, hole) > 0.97 * sharpness(raw, hole)


def test_only_the_neighbourhoods_near_the_hole_take_part(bricks):
    # Under hard constraints a neighbourhood wholly on known pixels votes only for pixels that every
    # E-step puts back, so inpaint searches and averages just the neighbourhoods that touch the hole
    # and one grid step around them; a hole inside the image needs no margin (the canvas is the image).
    hole = disc(bricks.shape[:2], (80, 84), 12)
    out, info = texsynth.inpaint(bricks, hole, neighborhood_sizes=(16, 8), levels=2, rng=0, return_info=True)
    np.testing.assert_array_equal(out[~hole], bricks[~hole])
    for stage in info.stages:
        assert stage.shape == tuple(-(-s // 2**stage.level) for s in bricks.shape[:2])  # no margin
    last = info.stages[-1]
    full = texsynth.core.neighborhood.grid_centers(bricks.shape[:2], last.size, last.spacing, mode="valid")
    assert last.neighborhoods == len(info.centers) < 0.15 * len(full)  # a disc of radius 12 in 160 x 160
    # every one of them within a grid step of touching the hole (a neighbourhood spans w // 2 each side)
    rows, cols = np.nonzero(hole)
    reach = last.size // 2 + last.spacing
    near = ((np.abs(info.centers[:, None, 0] - rows) <= reach) & (np.abs(info.centers[:, None, 1] - cols) <= reach))
    assert near.any(axis=1).all()
    # uncrop's free border reaches the edges: its canvas keeps the margin
    _, info = texsynth.uncrop(bricks[:64, :64], 96, neighborhood_sizes=(16, 8), levels=1, rng=0, return_info=True)
    assert info.stages[-1].shape == (96 + 8, 96 + 8)


def test_hard_constraints_alone_give_a_copy_map_everywhere(texture):
    # optimize_texture with constraint_weight=inf and a target that is not the exemplar: the pixels far
    # from the free ones are in no searched neighbourhood, and their map continues the nearest covered
    # pixel's, kept inside the exemplar, so apply_coordinates still renders the whole output
    ex = texture("jcjohnson/bread.png", 40)
    target = texture("rohitrango/t1.png", 64)
    mask = ~disc((64, 64), (32, 32), 6)
    out, info = optimize_texture(ex, 64, constraints=Constraints(mask=mask, target=target, constraint_weight=np.inf),
                                 schedule=Schedule(neighborhood_sizes=(8,), levels=1, max_iterations=2), rng=0,
                                 return_info=True)
    np.testing.assert_array_equal(out[mask], target[mask])
    c = info.coordinates
    assert c.shape == (64, 64, 2) and c.min() >= 0 and (c < 40).all()
    assert texsynth.apply_coordinates(ex, info).shape == (64, 64, 3)
    # right of the searched neighbourhoods (which end before column 50), row 32 continues the last
    # covered pixel's source one column per pixel (measured: (7, 18) ... (7, 31))
    np.testing.assert_array_equal(np.diff(c[32, 50:], axis=0), [[0, 1]] * 13)


def test_known_pixels_map_to_their_own_place_in_the_image(texture):
    # the source-coordinate map of a completion: a known pixel is the image's own pixel (for uncrop,
    # shifted by where the image lands), so apply_coordinates renders another channel of the image
    # unchanged there
    image = texture("jcjohnson/bread.png", 48)
    hole = disc(image.shape, (24, 24), 8)
    out, info = texsynth.inpaint(image, hole, neighborhood_sizes=(8,), levels=1, max_iterations=2, rng=0,
                                 return_info=True)
    rows, cols = np.nonzero(~hole)
    assert np.array_equal(info.coordinates[rows, cols], np.stack([rows, cols], 1))
    out, info = texsynth.uncrop(image, (64, 64), position=(4, 10), neighborhood_sizes=(8,), levels=1,
                                max_iterations=2, rng=0, return_info=True)
    assert np.array_equal(info.coordinates[4:52, 10:58], np.stack(np.mgrid[:48, :48], -1))
    channel = np.random.default_rng(0).random(image.shape[:2])
    assert np.array_equal(texsynth.apply_coordinates(channel, info)[4:52, 10:58], channel)


def test_inpaint_copies_only_from_the_sample_mask(texture):
    left = texture("jcjohnson/bread.png", 64)  # golden bread
    right = np.repeat(texture("lcv/metal.pgm", 64)[..., None], 3, axis=2) * 0.5  # dark grey metal
    image = np.concatenate([left, right], axis=1)
    hole = np.zeros((64, 128), bool)
    hole[20:44, 52:76] = True  # across the boundary of the two textures
    sample = np.zeros((64, 128), bool)
    sample[:, 64:] = True  # only the metal may be copied
    out = texsynth.inpaint(image, hole, sample_mask=sample, neighborhood_sizes=(16, 8), rng=0)
    filled = out[hole]
    # the fill's colour is the metal's, not the bread's (their means differ by 0.3-0.5 per channel)
    metal, bread = right.reshape(-1, 3).mean(0), left.reshape(-1, 3).mean(0)
    assert np.abs(filled.mean(0) - metal).max() < 0.1 < np.abs(filled.mean(0) - bread).max()


def test_uncrop_keeps_the_image_and_extends_it(bricks):
    img = bricks[:96, :96]
    out = texsynth.uncrop(img, (144, 160), rng=0)
    assert out.shape == (144, 160, 3)
    np.testing.assert_array_equal(out[24:120, 32:128], img)  # centred
    ring = np.ones((144, 160), bool)
    ring[16:128, 24:136] = False  # the synthesised border, away from the image
    # texture, not a smear: measured 0.84 of the image's sharpness (a 1-px blur keeps 0.45)
    assert sharpness(out, ring) / sharpness(img, np.ones((96, 96), bool)) > 0.6
    corner = texsynth.uncrop(img, 128, position=(0, 0), neighborhood_sizes=(16, 8), rng=0)
    np.testing.assert_array_equal(corner[:96, :96], img)


def test_soft_constraints_too_large_for_memory_are_refused_with_the_fix(monkeypatch):
    import texsynth.core._validate as validate

    monkeypatch.setattr(validate, "available_memory", lambda: 1e8)  # 100 MB free
    image = np.random.default_rng(0).random((256, 256, 3))
    with pytest.raises(ValueError, match=r"constraint_weight=float\('inf'\)"):
        optimize_texture(image, 256, constraints=Constraints(mask=np.ones((256, 256)), target=image,
                                                             constraint_weight=100.0))


@pytest.mark.parametrize("call, words", [
    (lambda img: texsynth.inpaint(img, np.zeros((32, 32), bool)), "hole marks no pixel"),
    (lambda img: texsynth.inpaint(img, np.ones((32, 32), bool)), "hole covers the whole image"),
    (lambda img: texsynth.inpaint(img, np.ones((30, 32), bool)), "hole must have shape"),
    (lambda img: texsynth.inpaint(img, disc((32, 32), (16, 16), 6), sample_mask=np.eye(32, dtype=bool)),
     "sample_mask leaves no"),
    (lambda img: texsynth.uncrop(img, 24), "size .* is smaller than the image"),
    (lambda img: texsynth.uncrop(img, 32), r"size \(32, 32\) is the image's size: nothing to fill; pass a size larger "
                                           r"than the image \(32, 32\) on at least one side"),
    (lambda img: texsynth.uncrop(img[:, :30], (32, 30)), "is the image's size"),
    (lambda img: texsynth.uncrop(img, 48, position=(20, 0)), "position"),
    (lambda img: texsynth.uncrop(img, 48, sample_mask=np.ones((3, 3))), "sample_mask must have shape"),
    (lambda img: texsynth.inpaint(img, disc((32, 32), (16, 16), 6), blend_width=-2), "blend_width must be an integer >= 0"),
    (lambda img: texsynth.uncrop(img, 48, blend_width=-1), "blend_width must be an integer >= 0"),
])
def test_bad_input_names_the_parameter(texture, call, words):
    with pytest.raises(ValueError, match=words):
        call(texture("jcjohnson/bread.png", 32))


@pytest.mark.parametrize("dtype, channels", [(np.float64, 3), (np.float32, 3), (np.float64, None)])
def test_the_memory_check_of_uncrop_bounds_what_is_allocated_before_optimize_texture_checks(monkeypatch, dtype,
                                                                                           channels):
    # uncrop checks the arrays it and optimize_texture allocate before optimize_texture checks its own (N11:
    # an uncrop that passed its check ran out of memory copying the target and the mask in optimize_texture)
    import tracemalloc

    import texsynth.optimization._completion as completion
    import texsynth.optimization._kwatra as kwatra

    class Checked(Exception):
        pass

    estimates, peaks = [], []
    check = completion.check_memory

    def estimate(nbytes, *args, **kwargs):
        estimates.append(nbytes)
        return check(nbytes, *args, **kwargs)

    def optimize_texture_checks(*args, **kwargs):  # from here on its own check counts the memory
        peaks.append(tracemalloc.get_traced_memory()[1])
        raise Checked

    shape = (48, 40) if channels is None else (48, 40, channels)
    image = np.random.default_rng(0).random(shape).astype(dtype)
    texsynth.uncrop(image, (64, 64), neighborhood_sizes=(8,), levels=1, max_iterations=1, rng=0)  # warm up
    monkeypatch.setattr(completion, "check_memory", estimate)
    monkeypatch.setattr(kwatra, "_check_memory", optimize_texture_checks)
    for kwargs in (dict(), dict(neighborhood_sizes=(64, 16, 8), position=(0, 0))):
        tracemalloc.start()
        try:
            with pytest.raises(Checked):
                texsynth.uncrop(image, (400, 300), rng=0, **kwargs)
        finally:
            tracemalloc.stop()
        assert estimates[-1] >= peaks[-1], kwargs


# --------------------------------------------------------------------------- the hole as artists have it (issue 34)
FAST = dict(neighborhood_sizes=(8,), levels=1, max_iterations=1, rng=0)


def _photo_and_hole():
    image = texsynth.data.load("bread")[:48, :48]
    hole = np.zeros((48, 48), bool)
    hole[16:30, 14:34] = True
    return image, hole


def test_hole_alpha_is_the_images_transparency():
    image, hole = _photo_and_hole()
    rgba = np.concatenate([image, np.where(hole, 0.0, 1.0)[..., None]], -1)
    rgba[hole, :3] = 0.0  # what a cut-out holds under its transparent pixels: ignored
    out = texsynth.inpaint(rgba, "alpha", **FAST)
    assert np.array_equal(out, texsynth.inpaint(rgba, hole, **FAST))  # alpha < 1 = fill
    assert out.shape == (48, 48, 4) and np.array_equal(out[~hole], rgba[~hole])
    assert np.all(out[hole, 3] == 1.0)  # the filled pixels take the alpha of those they copy: opaque here
    grey_alpha = np.stack([image.mean(-1), np.where(hole, 0.0, 1.0)], -1)
    assert np.array_equal(texsynth.inpaint(grey_alpha, "alpha", **FAST), texsynth.inpaint(grey_alpha, hole, **FAST))


def test_a_soft_transparent_edge_blends_into_the_fill_and_comes_back_opaque():
    image, hole = _photo_and_hole()
    rows, cols = np.mgrid[:48, :48]
    alpha = np.clip((np.hypot(rows - 23, cols - 24) - 5) / 6, 0, 1)  # transparent disc, feathered over 6 px
    rgba = np.concatenate([image, alpha[..., None]], -1)
    out = texsynth.inpaint(rgba, "alpha", **FAST)
    translucent = alpha < 1
    fill = texsynth.inpaint(rgba, translucent, **FAST)  # every pixel that is not opaque is filled ...
    a = alpha[..., None]
    expected = a * rgba[..., :3] + (1 - a) * fill[..., :3]  # ... and the image laid over the fill by its alpha
    assert np.allclose(out[..., :3], expected, atol=1e-12) and np.all(out[..., 3] == 1.0)
    assert np.array_equal(out[~translucent], rgba[~translucent])  # opaque pixels bit for bit


@pytest.mark.parametrize("layout", ["rgb", "grey"])
def test_hole_alpha_without_an_alpha_channel_is_a_clear_error(layout):
    image, _ = _photo_and_hole()
    image = image if layout == "rgb" else image.mean(-1)
    with pytest.raises(ValueError, match=r"hole='alpha' takes the hole from the image's alpha channel .* has none"):
        texsynth.inpaint(image, "alpha", **FAST)


def test_hole_may_be_an_image_file_white_is_fill(tmp_path):
    from texsynth.io import save_image

    image, hole = _photo_and_hole()
    expected = texsynth.inpaint(image, hole, **FAST)
    grey = save_image(tmp_path / "hole.png", hole.astype(float))
    rgba = save_image(tmp_path / "hole_rgba.png", np.stack([hole * 1.0] * 3 + [np.full(hole.shape, 0.3)], -1))
    for given in (str(grey), grey, str(rgba)):  # str or Path; colour averaged, alpha ignored
        assert np.array_equal(texsynth.inpaint(image, given, **FAST), expected), given
    with pytest.raises(ValueError, match=r"hole must be an \(H, W\) map, an image file or 'alpha', got 'Alpha'"):
        texsynth.inpaint(image, "Alpha", **FAST)


def test_a_hole_over_half_the_image_warns_with_its_share():
    import warnings

    image, hole = _photo_and_hole()
    with pytest.warns(UserWarning, match=r"the hole covers 88 % of the image \(white, True = fill\).*~hole"):
        texsynth.inpaint(image, ~hole, **FAST)  # Embark's mask (black = fill) taken as it is
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        texsynth.inpaint(image, hole, **FAST)  # 12 %: no warning
