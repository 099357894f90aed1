"""texsynth.core.seams: minimum-error boundary cuts (DP) and grid min-cuts with seam nodes, against brute force."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from texsynth.core.seams import (
    backtrack,
    GRADIENT_EPSILON,
    cumulative_cost,
    gradient_matching_cost,
    graph_cut,
    matching_cost,
    minimum_error_boundary,
    seam_mask,
)

# --------------------------------------------------------------------------- brute force references


def all_seams(h, w):
    """Every 8-connected top-to-bottom path: a start column and a step of -1, 0 or +1 per row."""
    for start in range(w):
        for steps in itertools.product((-1, 0, 1), repeat=h - 1):
            seam = np.cumsum((start,) + steps)
            if seam.min() >= 0 and seam.max() < w:
                yield seam


def seam_cost(cost, seam):
    return float(cost[np.arange(len(seam)), seam].sum())


def labelling_cost(old, new, labels, patches, side, mask):
    """The cost of the seams one labelling makes (Kwatra 2003, Section 3): M(s, t, X, Y) for every pair of
    neighbours taken from different images X, Y; an old seam left between two old pixels keeps its old cost."""
    def value(image_of, r, c):
        return image_of[r, c][None]

    h, w = side.shape
    total = 0.0
    for (r, c), (r2, c2) in [(((r, c)), (r, c + 1)) for r in range(h) for c in range(w - 1)] + \
                            [(((r, c)), (r + 1, c)) for r in range(h - 1) for c in range(w)]:
        if not (mask[r, c] and mask[r2, c2]):
            continue
        def source(rr, cc):  # the image the pixel shows under this labelling
            return new if side[rr, cc] else (old if labels is None else patches[labels[rr, cc]])
        x, y = source(r, c), source(r2, c2)
        if x is y:
            continue
        total += float(matching_cost(value(x, r, c), value(x, r2, c2), value(y, r, c), value(y, r2, c2))[0])
    return total


def brute_force_cut(old, new, mask, old_mask, new_mask, labels=None, patches=None):
    """The cheapest labelling of the free pixels, by enumeration."""
    free = np.argwhere(mask & ~old_mask & ~new_mask)
    best = (np.inf, None)
    for bits in itertools.product((False, True), repeat=len(free)):
        side = new_mask.copy()
        side[tuple(free.T)] = bits
        cost = labelling_cost(old, new, labels, patches, side, mask)
        if cost < best[0] - 1e-12:
            best = (cost, side)
    return best


# --------------------------------------------------------------------------- minimum-error boundary cut


@settings(max_examples=60, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 5), st.integers(1, 4)), elements=st.floats(0, 10)))
def test_the_seam_is_the_cheapest_of_all_paths(cost):
    h, w = cost.shape
    best = min(seam_cost(cost, s) for s in all_seams(h, w))
    seam = minimum_error_boundary(cost)
    assert seam.shape == (h,)
    assert np.all(np.abs(np.diff(seam)) <= 1) and seam.min() >= 0 and seam.max() < w  # 8-connected, inside
    assert seam_cost(cost, seam) == pytest.approx(best, abs=1e-9)
    # E_ij = e_ij + min of the three above: its last row holds every path's best ending there
    E = cumulative_cost(cost)
    for j in range(w):
        ends = [seam_cost(cost, s) for s in all_seams(h, w) if s[-1] == j]
        assert E[-1, j] == pytest.approx(min(ends), abs=1e-9)


def test_the_seam_follows_a_valley_and_horizontal_seams_are_transposed():
    rng = np.random.default_rng(0)
    cost = rng.uniform(1, 2, (40, 9))
    valley = np.clip(4 + np.cumsum(rng.integers(-1, 2, 40)), 0, 8)  # a random 8-connected path
    cost[np.arange(40), valley] = 0.0
    assert np.array_equal(minimum_error_boundary(cost), valley)
    assert np.array_equal(minimum_error_boundary(cost.T, direction="horizontal"), valley)
    assert np.array_equal(cumulative_cost(cost.T, direction="horizontal"), cumulative_cost(cost).T)
    assert np.array_equal(backtrack(cumulative_cost(cost)), valley)


def test_ties_go_straight_and_a_flat_cost_gives_a_straight_seam():
    assert minimum_error_boundary(np.zeros((6, 5))).tolist() == [0] * 6
    cost = np.ones((5, 5))
    cost[:, 3] = 0
    assert minimum_error_boundary(cost).tolist() == [3] * 5


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10**6), st.integers(1, 5), st.integers(1, 4), st.booleans())
def test_step_costs_the_seam_is_the_cheapest_of_all_paths(seed, h, w, horizontal):
    # seam carving's forward energy: a pixel cost plus the cost of the step into the pixel from the row above
    rng = np.random.default_rng(seed)
    cost, left, right = rng.random((h, w)), rng.random((h, w)), rng.random((h, w))

    def path_cost(seam):
        total = cost[0, seam[0]]
        for i in range(1, h):
            step = seam[i] - seam[i - 1]  # +1: from the upper left
            total += cost[i, seam[i]] + (left[i, seam[i]] if step == 1 else right[i, seam[i]] if step == -1 else 0)
        return total

    best = min(path_cost(s) for s in all_seams(h, w))
    if horizontal:  # the same problem, transposed
        seam = minimum_error_boundary(cost.T, direction="horizontal", step_costs=(left.T, None, right.T))
    else:
        seam = minimum_error_boundary(cost, step_costs=(left, None, right))
    assert np.all(np.abs(np.diff(seam)) <= 1) and seam.min() >= 0 and seam.max() < w
    assert path_cost(seam) == pytest.approx(best, abs=1e-9)
    zero = np.zeros((h, w))
    assert np.array_equal(cumulative_cost(cost, step_costs=(zero, zero, zero)), cumulative_cost(cost))


def test_the_same_path_as_scikit_image_mcp_restricted_to_downward_moves():
    from skimage.graph import MCP

    cost = np.random.default_rng(1).random((30, 12))
    mcp = MCP(cost, offsets=[(1, -1), (1, 0), (1, 1)], fully_connected=True)
    cumulative, _ = mcp.find_costs(starts=[(0, j) for j in range(12)])
    assert np.allclose(cumulative, cumulative_cost(cost))
    end = (29, int(np.argmin(cumulative[-1])))
    assert [c for _, c in mcp.traceback(end)] == minimum_error_boundary(cost).tolist()


def test_seam_mask_marks_the_pixels_before_the_seam():
    seam = np.array([1, 2, 0])
    mask = seam_mask(seam, (3, 4))
    assert mask.astype(int).tolist() == [[1, 0, 0, 0], [1, 1, 0, 0], [0, 0, 0, 0]]
    assert np.array_equal(seam_mask(seam, (4, 3), direction="horizontal"), mask.T)
    assert seam_mask(seam + 1, (3, 4)).sum() == mask.sum() + 3  # the seam's own pixels


@pytest.mark.parametrize("call, words", [
    (lambda: minimum_error_boundary(np.zeros(5)), "2-D"),
    (lambda: minimum_error_boundary(np.array([[np.nan]])), "NaN"),
    (lambda: minimum_error_boundary(np.zeros((2, 2)), direction="up"), "direction must be"),
    (lambda: cumulative_cost(np.array([["a"]])), "real numeric"),
    (lambda: seam_mask([0, 1], (3, 4)), "seam must hold 3 integers"),
    (lambda: seam_mask([0, 9, 1], (3, 4)), r"seam values must lie in 0..4"),
])
def test_bad_input_to_the_boundary_cut(call, words):
    with pytest.raises((ValueError, TypeError), match=words):
        call()


# --------------------------------------------------------------------------- graph cut


def _tiny_problem(rng, shape=(3, 4), channels=2):
    old = rng.random(shape + (channels,))
    new = rng.random(shape + (channels,))
    old_mask = np.zeros(shape, bool)
    new_mask = np.zeros(shape, bool)
    old_mask[:, 0] = True
    new_mask[:, -1] = True
    return old, new, old_mask, new_mask


@pytest.mark.parametrize("seed", range(6))
def test_the_min_cut_is_the_cheapest_labelling(seed):
    rng = np.random.default_rng(seed)
    old, new, old_mask, new_mask = _tiny_problem(rng)
    mask = np.ones(old.shape[:2], bool)
    if seed % 2:  # an overlap that is not a rectangle
        mask[0, 1] = False
    best, _ = brute_force_cut(old, new, mask, old_mask, new_mask)
    side, cost = graph_cut(old, new, mask=mask, old_mask=old_mask, new_mask=new_mask)
    assert cost == pytest.approx(best, rel=1e-6)
    assert labelling_cost(old, new, None, None, side, mask) == pytest.approx(cost, rel=1e-12)
    assert not side[~mask].any() and side[new_mask].all() and not side[old_mask].any()


@pytest.mark.parametrize("seed", range(6))
def test_seam_nodes_charge_what_the_labelling_keeps_of_old_seams(seed):
    """Two old patches meet along a vertical old seam; the brute force prices every labelling by the seams it
    makes (old seams kept pay their old cost): the cut with seam nodes finds the cheapest."""
    rng = np.random.default_rng(100 + seed)
    shape = (3, 4)
    patches = rng.random((2,) + shape + (1,))
    labels = np.zeros(shape, int)
    labels[:, 2:] = 1  # the old output: patch 0 left, patch 1 right, an old seam between columns 1 and 2
    if seed % 2:
        labels[0, 1] = 1  # a stepped old seam
    old = patches[labels, np.arange(3)[:, None], np.arange(4)[None, :]]
    new = rng.random(shape + (1,))
    old_mask = np.zeros(shape, bool)
    new_mask = np.zeros(shape, bool)
    old_mask[0, 0] = True
    new_mask[2, 3] = True
    mask = np.ones(shape, bool)
    best, _ = brute_force_cut(old, new, mask, old_mask, new_mask, labels, patches)
    side, cost = graph_cut(old, new, old_mask=old_mask, new_mask=new_mask, labels=labels, patches=patches)
    assert cost == pytest.approx(best, rel=1e-6)
    assert labelling_cost(old, new, labels, patches, side, mask) == pytest.approx(cost, rel=1e-9)


def test_a_seam_node_lets_a_new_patch_cover_an_expensive_old_seam():
    """Constructed case: old patch 0 (all 0) left of an old seam, old patch 1 (all 1) right of it, the first and
    last columns constrained to stay old. The old seam costs M = |0 - 1| + |0 - 1| = 2 per row. A flat new patch
    of 0.5 can only replace it by two seams of M = 1 per row: a tie. A new patch that
    continues patch 0 on the left of the old seam and patch 1 on its right replaces it by two seams of 0.5: the
    cut takes it. Without seam nodes (no labels) the old seam is invisible and nothing is gained."""
    shape = (4, 6)
    left_patch = np.zeros(shape + (1,))
    right_patch = np.ones(shape + (1,))
    labels = np.zeros(shape, int)
    labels[:, 3:] = 1
    patches = np.stack([left_patch, right_patch])
    old = patches[labels, np.arange(4)[:, None], np.arange(6)[None, :]]
    new = np.full(shape + (1,), 0.5)  # halfway: cutting it in costs 0.5 + 0.5 per pair; the old seam costs 2
    old_mask = np.zeros(shape, bool)
    old_mask[:, 0] = True
    old_mask[:, -1] = True  # both ends stay old
    side, cost = graph_cut(old, new, old_mask=old_mask, labels=labels, patches=patches)
    assert cost == pytest.approx(8.0)  # 4 rows x 2 either way; of tied cuts the one with the fewest old pixels:
    assert side[:, 1:5].all() and not side[:, [0, 5]].any()
    new[:, 2] = 0.0  # the new patch continues patch 0 on the left of the old seam ...
    new[:, 3] = 1.0  # ... and patch 1 on its right
    side, cost = graph_cut(old, new, old_mask=old_mask, labels=labels, patches=patches)
    assert cost == pytest.approx(4.0)  # two seams of |0 - 0.5| + 0 and 0 + |0.5 - 1| per row
    assert side[:, 2:4].any()
    plain_side, plain_cost = graph_cut(old, new, old_mask=old_mask)  # no seam nodes: nothing to gain
    assert plain_cost == 0.0 and not plain_side.any()


def test_without_constraints_everything_takes_the_new_patch_at_no_cost():
    rng = np.random.default_rng(3)
    side, cost = graph_cut(rng.random((5, 5)), rng.random((5, 5)))
    assert side.all() and cost == 0.0


def test_integer_scaling_loses_at_most_the_documented_precision():
    """Costs from 1e-6 to 2e3 in one graph. Scaled to integers summing to 2**30, a cost below S / 2**31 (S the
    sum of all costs) rounds to 0, so the cut may pick a slightly dearer seam, but never by more than
    n_arcs * S / 2**30; and cut_cost is the labelling's cost in float64."""
    old = np.zeros((6, 8))
    new = np.full((6, 8), 1e3)
    new[:, 4] = old[:, 4] = 0.5
    new[:, 3] = 1e-6  # the pairs (3, 4) cost |0 - 1e-6| + |0.5 - 0.5| = 1e-6
    old_mask = np.zeros((6, 8), bool)
    old_mask[:, 0] = True
    new_mask = np.zeros((6, 8), bool)
    new_mask[:, -1] = True
    side, cost = graph_cut(old, new, old_mask=old_mask, new_mask=new_mask)
    assert side[:, 4:].all() and not side[:, :4].any()  # the cheap column pair, although 1e-6 rounds to 0
    assert cost == pytest.approx(6e-6, rel=1e-9)
    # a random problem with a wide range of costs: within the bound of the exact optimum
    rng = np.random.default_rng(7)
    old, new, old_mask, new_mask = _tiny_problem(rng)
    new *= 10.0 ** rng.integers(-6, 1, new.shape)
    best, _ = brute_force_cut(old, new, np.ones((3, 4), bool), old_mask, new_mask)
    _, cost = graph_cut(old, new, old_mask=old_mask, new_mask=new_mask)
    everything = labelling_cost(old, new, None, None, np.indices((3, 4)).sum(0) % 2 == 1, np.ones((3, 4), bool))
    assert best <= cost <= best + 2 * 17 * everything / 2**30  # 17 pairs, both directions


def test_interactive_merging_keeps_what_the_user_marked():
    """Two photographs-to-be with user strokes: the seam runs where they agree, the strokes are honoured."""
    rng = np.random.default_rng(5)
    a = rng.random((12, 12, 3))
    b = rng.random((12, 12, 3))
    b[:, 5:7] = a[:, 5:7]  # the images agree in a band
    stroke_a = np.zeros((12, 12), bool)
    stroke_a[2:10, 1] = True
    stroke_b = np.zeros((12, 12), bool)
    stroke_b[2:10, 10] = True
    side, cost = graph_cut(a, b, old_mask=stroke_a, new_mask=stroke_b)
    assert not side[stroke_a].any() and side[stroke_b].all()
    assert cost == pytest.approx(labelling_cost(a, b, None, None, side, np.ones((12, 12), bool)))
    assert side[:, 7:].all() and not side[:, :5].any()  # the seam lies inside the band where they agree


def test_the_gradient_normalised_cost_divides_m_by_the_gradients_along_the_arc():
    """M' = M / (||G_A(s)|| + ||G_A(t)|| + ||G_B(s)|| + ||G_B(t)|| + eps), each gradient the difference along the
    arc; so of two seams with the same M, the one along an edge of the images is the cheaper."""
    rng = np.random.default_rng(2)
    a_s, a_t, b_s, b_t = (rng.random((50, 3)) for _ in range(4))
    gradients = 2 * (np.linalg.norm(a_t - a_s, axis=1) + np.linalg.norm(b_t - b_s, axis=1))
    assert np.allclose(gradient_matching_cost(a_s, a_t, b_s, b_t),
                       matching_cost(a_s, a_t, b_s, b_t) / (gradients + GRADIENT_EPSILON))
    # old and new differ by 0.2 everywhere; columns 0-2 are flat, column 3 onwards is a step up: an edge
    old = np.zeros((4, 7))
    old[:, 4:] = 0.8
    new = old + 0.2
    left, right = np.zeros((4, 7), bool), np.zeros((4, 7), bool)
    left[:, 0], right[:, -1] = True, True
    plain, _ = graph_cut(old, new, old_mask=left, new_mask=right)
    side, cost = graph_cut(old, new, old_mask=left, new_mask=right, edge_cost=gradient_matching_cost)
    assert np.array_equal(side, np.broadcast_to(np.arange(7) >= 4, (4, 7)))  # the seam runs along the edge
    assert cost == pytest.approx(4 * 0.4 / (2 * 1.6 + GRADIENT_EPSILON))
    assert plain[:, 1:].all()  # M alone costs 0.4 a row everywhere: of the tied cuts, the fewest old pixels


@pytest.mark.parametrize("kwargs, words", [
    ({"new": np.zeros((3, 5))}, "same shape"),
    ({"old_mask": np.ones((3, 4), bool), "new_mask": np.ones((3, 4), bool)}, "both hold 12 pixels"),
    ({"old_mask": np.ones((3, 4))}, "bool array of shape"),
    ({"mask": np.eye(3, 4, dtype=bool), "old_mask": np.ones((3, 4), bool)}, "outside mask"),
    ({"labels": np.zeros((3, 4), int)}, "labels and patches go together"),
    ({"labels": np.full((3, 4), 2), "patches": np.zeros((2, 3, 4))}, r"labels must lie in 0..1"),
    ({"labels": np.zeros((3, 4), int), "patches": np.ones((1, 3, 4))}, "old differs from patches"),
    ({"edge_cost": lambda a_s, a_t, b_s, b_t: -np.ones(len(a_s))}, "negative"),
    ({"old": np.full((3, 4), np.inf)}, "NaN or infinite"),
])
def test_bad_input_to_the_graph_cut(kwargs, words):
    args = {"old": np.zeros((3, 4)), "new": np.ones((3, 4))}
    args.update(kwargs)
    with pytest.raises((ValueError, TypeError), match=words):
        graph_cut(args.pop("old"), args.pop("new"), **args)


# --------------------------------------------------------------------------- gradient-domain blending
def test_a_fill_offset_from_the_known_pixels_is_brought_level_with_them_across_the_band():
    from texsynth.core.seams import poisson_blend

    # a flat image whose right half (the fill) is 0.5 too bright: with the band over the whole fill the offset
    # goes everywhere (the membrane of a constant mismatch is that constant), the known half bit for bit
    flat = np.full((12, 40, 2), 0.25)
    known = np.zeros((12, 40), bool)
    known[:, :20] = True
    stepped = flat + 0.5 * ~known[..., None]
    out = poisson_blend(stepped, known, blend_width=40)
    np.testing.assert_allclose(out, flat, atol=1e-9)
    np.testing.assert_array_equal(out[known], flat[known])
    # with a narrower band only the pixels within it move, the offset fading across it (measured 0.083 left at
    # its first column, 0.417 at its last: 0.5 / 6 and 0.5 * 5 / 6); the rest keep the step
    narrow = poisson_blend(stepped, known, blend_width=5)
    np.testing.assert_array_equal(narrow[:, 26:], stepped[:, 26:])
    assert np.abs(narrow[:, 20] - flat[:, 20]).max() < 0.1
    assert 0.3 < np.abs(narrow[:, 24] - flat[:, 24]).max() < 0.5
    # width 0, or nothing known, changes nothing
    np.testing.assert_array_equal(poisson_blend(stepped, known, blend_width=0), stepped)
    np.testing.assert_array_equal(poisson_blend(stepped, np.zeros((12, 40), bool)), stepped)


def test_the_blend_hides_a_step_in_a_photograph_and_keeps_its_texture(texture):
    from texsynth.core.seams import poisson_blend

    photo = texture("jcjohnson/bread.png", 96)
    known = np.zeros((96, 96), bool)
    known[:, :48] = True
    fill = photo.copy()
    fill[:, 48:] = np.clip(photo[:, 48:] - 0.15, 0, 1)  # the right half darker: a step at column 48
    out = poisson_blend(fill, known)
    assert out.dtype == np.float64 and out.shape == photo.shape and 0 <= out.min() and out.max() <= 1
    np.testing.assert_array_equal(out[known], photo[known])

    def step(img):  # the mean signed difference across the border, per channel
        return np.abs((img[:, 48] - img[:, 47]).mean(axis=0)).max()

    def sharp(img, cols):
        return np.abs(np.diff(img[:, cols], axis=0)).mean() + np.abs(np.diff(img[:, cols], axis=1)).mean()

    # measured: the photograph itself steps by 0.004 there, the darkened fill by 0.147, blended 0.004
    assert step(out) < 0.03 < 0.1 < step(fill)
    # the fill's texture stays: the band's sharpness 1.01 of the darkened fill's (a Gaussian blur of sigma 1
    # px keeps 0.46 of it)
    band = slice(48, 80)
    assert abs(sharp(out, band) / sharp(fill, band) - 1) < 0.05
    np.testing.assert_array_equal(out[:, 80:], fill[:, 80:])  # over 32 px from the known pixels, untouched


def test_the_texture_s_own_steps_along_the_border_are_not_smeared_into_it(texture, monkeypatch):
    import texsynth.core.seams as seams

    # a fill that continues the photograph exactly: its steps at the border are the texture's, changing from
    # pixel to pixel along it, and smoothed along the border they nearly cancel. Measured: the blend moves it
    # by at most 0.045 (0.0026 on average over the band); without the smoothing (sigma 0.001 px) by 0.085
    photo = texture("jcjohnson/bread.png", 96)
    known = np.zeros((96, 96), bool)
    known[:, :48] = True
    smoothed = np.abs(seams.poisson_blend(photo, known) - photo).max()
    monkeypatch.setattr(seams, "BLEND_SMOOTHING", 1e-3)
    pixelwise = np.abs(seams.poisson_blend(photo, known) - photo).max()
    assert smoothed < 0.06 and smoothed < 0.7 * pixelwise


@pytest.mark.parametrize("kwargs, words", [
    (dict(mask=np.zeros((4, 4), bool)), "mask must be a bool array of shape"),
    (dict(mask=np.zeros((8, 8))), "mask must be a bool array of shape"),
    (dict(sample_mask=np.ones((8, 3), bool)), "sample_mask must be a bool array of shape"),
    (dict(blend_width=-1), "blend_width must be an integer >= 0"),
    (dict(blend_width=2.5), "blend_width must be an integer >= 0"),
])
def test_bad_input_to_the_blend(kwargs, words):
    from texsynth.core.seams import poisson_blend

    args = dict(mask=np.eye(8, dtype=bool)) | kwargs
    with pytest.raises((ValueError, TypeError), match=words):
        poisson_blend(np.zeros((8, 8)), args.pop("mask"), **args)


def test_the_fill_is_blended_only_into_the_known_pixels_it_may_copy_from(texture):
    from texsynth.core.seams import poisson_blend

    # bread (known) | a metal fill | metal (known): blended into both sides, the fill takes the bread's colour
    # on its left; blended only into the metal it was copied from (``sample_mask``), it stays metal there
    bread, metal = texture("jcjohnson/bread.png", 48), np.repeat(texture("lcv/metal.pgm", 48)[..., None], 3, 2) * 0.5
    image = np.concatenate([bread, metal, metal], axis=1)
    known = np.ones((48, 144), bool)
    known[:, 48:96] = False
    into = known.copy()
    into[:, :48] = False
    left = slice(48, 56)  # the fill's first 8 columns, beside the bread
    both, only = poisson_blend(image, known), poisson_blend(image, known, sample_mask=into)
    # measured: the colours differ by up to 0.62; the fill's left columns moved 0.57 towards the bread when
    # blended into both, 0.0 when blended into the metal only
    gap = np.abs(bread.mean((0, 1)) - metal.mean((0, 1))).max()
    assert np.abs(both[:, left].mean((0, 1)) - image[:, left].mean((0, 1))).max() > 0.3 * gap
    assert np.abs(only[:, left].mean((0, 1)) - image[:, left].mean((0, 1))).max() < 0.02


def test_a_blend_too_large_for_memory_is_refused_before_anything_is_allocated(monkeypatch):
    import texsynth.core._validate as validate
    from texsynth.core.seams import poisson_blend

    monkeypatch.setattr(validate, "available_memory", lambda: 1e6)  # 1 MB free
    known = np.zeros((256, 256), bool)
    known[64:192, 64:192] = True
    with pytest.raises(ValueError, match="image=.*gradient-domain blend"):
        poisson_blend(np.zeros((256, 256)), known)


def test_a_line_of_the_texture_along_the_border_is_not_taken_for_an_offset(monkeypatch):
    import texsynth.core.seams as seams

    # a light line just inside the fill along 8 px of the border (a mortar joint beside a hole's rim) and, on
    # the same image, the whole fill 0.3 too light. Measured: the line stays (moved 0.0; 0.16 if every border
    # tie is trusted alike), the offset goes (0.004 of 0.3 left at the border)
    rng = np.random.default_rng(0)
    image = 0.6 + 0.02 * rng.standard_normal((40, 60))
    known = np.zeros((40, 60), bool)
    known[:20] = True
    lined = image.copy()
    lined[20, 25:33] = 0.9
    offset = image.copy()
    offset[20:] += 0.3
    assert np.abs(seams.poisson_blend(lined, known)[20, 25:33] - 0.9).max() < 0.03
    assert np.abs(seams.poisson_blend(offset, known)[20] - image[20]).mean() < 0.03
    monkeypatch.setattr(seams, "_BLEND_TRUST_STEPS", 1e9)  # every tie trusted: the line is shaded
    assert np.abs(seams.poisson_blend(lined, known)[20, 25:33] - 0.9).max() > 0.1
