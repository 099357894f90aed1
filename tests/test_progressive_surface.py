"""Progressively-variant textures on surfaces (surface._progressive_surface; Zhang et al. 2003; issue 36, item 2).

The texton masks and the feature-based warping between two exemplars (texsynth.core.textons) are tested here
too; find_textons' planar use in tests/test_texton.py.
"""

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.csgraph
from scipy.ndimage import label

from texsynth.core.search import Search
from texsynth.core.textons import element_warp, find_textons, progressive_sample
from texsynth.surface import progressive_surface
from texsynth.surface._shapes import sphere
from texsynth.surface._vertex_synthesis import SurfaceSchedule

SCHEDULE = SurfaceSchedule(levels=2, neighborhood_size=7, parent_size=5)
SEEDS = (0, 1)


def _spots(size, spacing, radius, spot, ground, seed):
    """Round spots of colour ``spot`` on ``ground`` (toroidal), on a jittered grid, with a little noise."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:size, 0:size]
    inside = np.zeros((size, size), bool)
    for y in range(spacing // 2, size, spacing):
        for x in range(spacing // 2, size, spacing):
            cy, cx = y + rng.uniform(-1.5, 1.5), x + rng.uniform(-1.5, 1.5)
            dy, dx = (rows - cy + size / 2) % size - size / 2, (cols - cx + size / 2) % size - size / 2
            inside |= dy ** 2 + dx ** 2 <= radius ** 2
    image = np.where(inside[..., None], np.array(spot), np.array(ground))
    return np.clip(image + 0.03 * rng.standard_normal(image.shape), 0, 1)


A = _spots(48, 12, 3.0, (0.3, 0.2, 0.1), (0.9, 0.8, 0.6), 0)
B = _spots(48, 16, 5.0, (0.5, 0.7, 0.4), (0.25, 0.3, 0.35), 1)


def _north(points):
    return (points[:, 2] + 1) / 2


@pytest.fixture(scope="module")
def runs():
    return [progressive_surface(sphere(642), A, B, _north, n_vertices=3000, schedule=SCHEDULE, rng=seed,
                                return_info=True) for seed in SEEDS]


def test_the_sample_runs_from_one_exemplar_to_the_other():
    mask_a, mask_b = find_textons(A), find_textons(B)
    image, mask, blend = progressive_sample(A, B, (mask_a, mask_b), width=192)
    assert image.shape == (48, 192, 3) and mask.shape == blend.shape == (48, 192)
    assert blend[0, 0] == 0 and blend[0, -1] == 1
    np.testing.assert_allclose(image[:, 0], A[:, 0])               # F = 0: the first exemplar itself
    np.testing.assert_allclose(image[:, -1], B[:, 191 % 48])        # F = 1: the second one (tiled)
    np.testing.assert_array_equal(mask[:, 0], mask_a[:, 0])
    assert np.abs(element_warp((mask_a, mask_b), [0.5])).max() > 1  # partners are not where the elements are


def test_the_warp_moves_and_scales_an_element_onto_its_partner():
    a = np.zeros((32, 32), bool)
    a[4:9, 4:9] = True     # 5 x 5, centre (6, 6)
    b = np.zeros((32, 32), bool)
    b[10:17, 8:15] = True  # 7 x 7, centre (13, 11)
    u = element_warp((a, b), [0.0, 1.0])
    np.testing.assert_allclose(u[0], 0, atol=1e-12)
    np.testing.assert_allclose(u[1, 13, 11], [-7, -5], atol=0.5)  # the partner's centre reads the element's
    _, mask, blend = progressive_sample(a.astype(float), b.astype(float), (a, b), width=17)
    # column 8 (F = 1/2): one element half way and of the middle size (rows 7-12), not both in place
    assert blend[0, 8] == 0.5
    half = mask[:, 8]
    assert half[7:13].all() and not half[:7].any() and not half[13:].any()


def test_along_blend_the_statistics_move_from_one_exemplar_to_the_other(runs):
    mean_a, mean_b = A.reshape(-1, 3).mean(0), B.reshape(-1, 3).mean(0)
    axis = (mean_b - mean_a) / np.sum((mean_b - mean_a) ** 2)
    for out, info in runs:
        bins = np.minimum((info.blend * 4).astype(int), 3)
        share = [float((out.colors[bins == q].mean(0) - mean_a) @ axis) for q in range(4)]
        # monotone from A (0) to B (1), each step at least 0.05 of the way (0.13-0.33 measured, seeds 0-4)
        assert all(s1 - s0 > 0.05 for s0, s1 in zip(share, share[1:])), share
        assert share[0] < 0.3 and share[-1] > 0.7, share  # 0.14-0.22 and 0.83-0.94 measured, seeds 0-4
        # each vertex copies the part of the sample whose F is its own: far closer than a random copy (ratio
        # 0.08-0.09 measured, seeds 0-4)
        copied = info.sample_blend[info.sources[:, 0], info.sources[:, 1]]
        shuffled = np.random.default_rng(0).permutation(copied)
        assert np.mean(np.abs(copied - info.blend)) < 0.4 * np.mean(np.abs(shuffled - info.blend))


def _fragment_share(sizes, whole):
    """The share of the mask's area in components smaller than a quarter of a whole element."""
    return float(sizes[sizes < whole / 4].sum() / sizes.sum())


def _mesh_sizes(mesh, mask, pixel_area):
    i, j = mesh.edges.T
    keep = mask[i] & mask[j]
    n = len(mask)
    graph = scipy.sparse.csr_matrix((np.ones(int(keep.sum())), (i[keep], j[keep])), shape=(n, n))
    _, labels = scipy.sparse.csgraph.connected_components(graph, directed=False)
    sizes = np.bincount(labels[mask])
    return sizes[sizes > 0] * (mesh.face_areas.sum() / n) / pixel_area  # in sample pixels


def test_elements_are_not_cut_more_often_than_in_the_sample(runs):
    for out, info in runs:
        labels, _ = label(info.sample_mask)
        whole_sizes = np.bincount(labels.ravel())[1:]
        whole = np.median(whole_sizes)
        in_sample = _fragment_share(whole_sizes, whole)
        shown = info.sample_mask[info.sources[:, 0], info.sources[:, 1]]
        on_mesh = _fragment_share(_mesh_sizes(out, shown, info.pixel_size ** 2), whole)
        # baseline: the same copies in a random arrangement over the vertices
        shuffled = np.random.default_rng(0).permutation(shown)
        random = _fragment_share(_mesh_sizes(out, shuffled, info.pixel_size ** 2), whole)
        # margin 0.1 of the mask's area over the sample's own share (mesh vs pixel connectivity; measured: sample
        # 0, mesh 0-0.012, random arrangement 0.78-1.0, seeds 0-4)
        assert on_mesh <= in_sample + 0.1, (on_mesh, in_sample)
        assert random > on_mesh + 0.3, (random, on_mesh)
        # the texture shows the mask synthesised first: elements where the mask put them
        assert np.mean(shown == info.texton_mask) > 0.85  # 0.987-0.996 measured, seeds 0-4


def test_same_seed_same_result_and_info(runs):
    out, info = runs[0]
    again = progressive_surface(sphere(642), A, B, _north, n_vertices=3000, schedule=SCHEDULE, rng=SEEDS[0])
    np.testing.assert_array_equal(out.colors, again.colors)
    assert info.texton_mask.shape == (len(out.vertices),) and info.field.shape == (len(out.vertices), 3)
    assert set(info.stage_seconds) >= {"sample", "hierarchy", "field", "mask level 0", "texture level 0"}


def test_per_vertex_blend_and_no_mask():
    ball = sphere(642)
    blend = (ball.vertices[:, 0] + 1) / 2
    out, info = progressive_surface(ball, A, B, blend, texton_mask=None, schedule=SCHEDULE, rng=0,
                                    return_info=True)
    assert len(out.vertices) == 642 and info.texton_mask is None
    np.testing.assert_allclose(info.blend, blend)


@pytest.mark.parametrize("kwargs, match", [
    (dict(blend=np.full(5, 0.5)), "blend"),
    (dict(blend=lambda p: p[:, 2] * 2), "blend"),
    (dict(blend=lambda p: p[:, :2]), "blend"),
    (dict(exemplar_b=B[..., 0]), "exemplar_b"),
    (dict(texton_mask=(np.zeros((4, 4)), np.zeros((48, 48)))), "texton_mask"),
    (dict(texton_mask="otsu"), "texton_mask"),
    (dict(texton_weight=-1.0), "texton_weight"),
    (dict(blend_weight=np.nan), "blend_weight"),
    (dict(schedule=SurfaceSchedule(order="sweep")), "order"),
    (dict(search=Search(candidates="all")), "candidates"),
    (dict(schedule=SurfaceSchedule(levels=5)), "levels"),
])
def test_bad_input_names_the_parameter(kwargs, match):
    args = dict(exemplar_b=B, blend=_north)
    args.update(kwargs)
    with pytest.raises((ValueError, TypeError), match=match):
        progressive_surface(sphere(642), A, args.pop("exemplar_b"), args.pop("blend"), **{"schedule": SCHEDULE,
                                                                                           **args})
