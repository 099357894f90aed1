"""Vertex synthesis on surfaces (texsynth.surface._vertex_synthesis; Turk 2001, Wei & Levoy 2001; issue 20, part 1).

Retiling and the fields it stands on are tested in tests/test_retile.py and tests/test_field.py.
"""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from texsynth.data import load
from texsynth.surface._field import tangent_field
from texsynth.surface._retile import retile
from texsynth.surface._shapes import sphere, torus
from texsynth.core.search import Search
from texsynth.surface._vertex_synthesis import SurfaceSchedule, synthesize_surface

from conftest import load_texture


TWO = SurfaceSchedule(levels=2)


def _stripes(size=48, period=8):
    """Horizontal stripes (constant along rows' x axis), with a little noise so neighbourhoods differ."""
    rng = np.random.default_rng(0)
    rows = np.arange(size)[:, None] * np.ones((1, size))
    return np.clip(0.5 + 0.4 * np.sin(2 * np.pi * rows / period) + 0.03 * rng.standard_normal((size, size)), 0, 1)


def _radial_spectrum(images, bins=8):
    """Mean radially averaged power spectrum of grey square images (without the mean), normalised to sum 1."""
    n = images.shape[-1]
    f = np.fft.fftfreq(n)
    r = np.hypot(f[:, None], f[None, :])
    edges = np.linspace(0, 0.5, bins + 1)
    power = np.abs(np.fft.fft2(images - images.mean(axis=(-2, -1), keepdims=True))) ** 2
    spectrum = np.array([power[..., (r > a) & (r <= b)].mean() for a, b in zip(edges[:-1], edges[1:])])
    return spectrum / spectrum.sum()


def _flattened_views(mesh, colors, field, pixel_size, centers, size=16):
    """Grey ``size x size`` views of the vertex colours on a grid laid along the field at each centre."""
    n = mesh.vertex_normals
    b = np.cross(n, field)
    r, c = np.mgrid[0:size, 0:size] - size // 2
    grid = (mesh.vertices[centers, None, None] + pixel_size * (c[None, ..., None] * field[centers, None, None]
                                                          - r[None, ..., None] * b[centers, None, None]))
    _, near = cKDTree(mesh.vertices).query(grid.reshape(-1, 3))
    return colors.mean(axis=1)[near].reshape(len(centers), size, size)


@pytest.mark.parametrize("preset", ["default", "paper"])
def test_element_scale_matches_the_exemplar_everywhere_on_a_torus(preset):
    ex = load_texture("skimage/gravel.png", 64, rgb=True)
    ex = ex if ex.ndim == 3 else ex[..., None]
    out, info = synthesize_surface(torus(2500), ex, n_vertices=6000, schedule=TWO, rng=0, preset=preset,
                                   return_info=True)
    rng = np.random.default_rng(1)
    centers = rng.choice(len(out.vertices), 60, replace=False)
    views = _flattened_views(out, out.colors, info.field, info.pixel_size, centers)
    crops = np.stack([ex[i:i + 16, j:j + 16].mean(axis=2) for i in range(0, 48, 8) for j in range(0, 48, 8)])
    target = _radial_spectrum(crops)
    # baseline: the same vertex colours shuffled over the surface (no spatial structure, the exemplar's histogram)
    shuffled = _flattened_views(out, out.colors[rng.permutation(len(out.colors))], info.field, info.pixel_size, centers)

    def distance(v):
        return np.abs(np.log(_radial_spectrum(v)) - np.log(target)).mean()

    synth, noise = distance(views), distance(shuffled)
    # calibrated: shuffled colours are white (flat spectrum) and measured 2.15-2.21 from gravel's; the synthesis
    # 0.25 (0.20 with seed 1) on Turk's nested hierarchy (0.20 and 0.17 on levels retiled each on its own; 0.17
    # before the nearest-vertex resampling), the paper preset's sweep 0.22-0.25 (seeds 0-2). A quarter of the
    # baseline's distance fails for colours that lost the element scale.
    assert synth < 0.25 * noise
    # uniform over the surface: the spectral centroid (in frequency bins) of the views on the inner and outer
    # halves of the torus (curved differently) measured 1.03 and 0.99 (0.98 and 1.04 with seed 1; the paper
    # preset 0.92-1.02 and 0.95-1.06, seeds 0-2), the exemplar's 0.97 and the shuffled colours' 3.70; both halves
    # must be within 25 % of the exemplar's
    radial = np.hypot(out.vertices[centers, 0], out.vertices[centers, 1])
    freqs = np.arange(8) + 0.5

    def centroid(v):
        s = _radial_spectrum(v)
        return (s * freqs).sum()

    inner, outer, reference = centroid(views[radial < 1.0]), centroid(views[radial >= 1.0]), centroid(crops)
    assert abs(inner - reference) < 0.25 * reference and abs(outer - reference) < 0.25 * reference


def _gradient_energy(mesh, directions):
    """Squared colour differences along the mesh edges, shared out to each of ``directions`` (N, 3) unit fields
    by the squared cosine of the edge's angle with it: large along a direction the colour changes in."""
    i, j = mesh.edges.T
    e = mesh.vertices[j] - mesh.vertices[i]
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    dc = ((mesh.colors[j] - mesh.colors[i]) ** 2).sum(axis=1)
    keep = np.abs(mesh.vertices[i, 2]) < 0.8  # away from the poles (the fields' singularities)
    return [float((dc * np.einsum("ij,ij->i", e, d[i]) ** 2)[keep].sum()) for d in directions]


def test_user_field_turns_the_texture():
    ex = _stripes()
    s = sphere(642)
    kw = dict(n_vertices=3000, schedule=TWO, rng=0)

    def east(p):
        return np.cross([0, 0, 1.0], p)

    def north(p):
        return np.cross(p, east(p))

    ratios = []
    for field in (east, north):
        out = synthesize_surface(s, ex, field=field, **kw)
        unit = [d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
                for d in (east(out.vertices), north(out.vertices))]
        along_east, along_north = _gradient_energy(out, unit)
        ratios.append(along_north / along_east)
    # Horizontal stripes laid along the field: the colour changes across the field more than along it. A
    # random field (candidates="all") measured 0.98-1.01 over two seeds; the oriented results 1.89-1.93 (east
    # field) and 0.48-0.49 (north field): the noise of the stripes and the irregular vertices add energy in
    # every direction. Thresholds 1.4 and 0.7 sit between the baseline and the measured values.
    assert ratios[0] > 1.4
    assert ratios[1] < 0.7


@pytest.mark.parametrize("shape", [sphere(642), torus(900)])
def test_stripes_follow_the_smooth_field(shape):
    # Every level must use one field: stripes synthesised along the relaxed field change colour across it
    # (along n x t) more than along it. Measured 1.90-1.97 (sphere) and 2.02-2.09 (torus) over seeds 0-1; a
    # random field gives about 1.0 (see test_user_field_turns_the_texture). Threshold 1.4 between.
    out, info = synthesize_surface(shape, _stripes(), n_vertices=3000, schedule=TWO, rng=0, return_info=True)
    t = info.field
    b = np.cross(out.vertex_normals, t)
    i, j = out.edges.T
    e = out.vertices[j] - out.vertices[i]
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    dc = ((out.colors[j] - out.colors[i]) ** 2).sum(axis=1)
    across = (dc * np.einsum("ij,ij->i", e, b[i]) ** 2).sum()
    along = (dc * np.einsum("ij,ij->i", e, t[i]) ** 2).sum()
    assert across > 1.4 * along


def test_synthesis_copies_exemplar_pixels_and_repeats_with_rng():
    ex = load("bread")[:40, :40]
    s = sphere(162)
    a, info = synthesize_surface(s, ex, n_vertices=800, schedule=TWO, rng=5, return_info=True)
    b = synthesize_surface(s, ex, n_vertices=800, schedule=TWO, rng=5)
    assert np.array_equal(a.colors, b.colors)
    # every colour is the exemplar pixel at the recorded source
    assert np.allclose(a.colors, ex[info.sources[:, 0], info.sources[:, 1]], atol=1e-6)
    assert len(info.levels) == 2 and len(info.levels[1].vertices) < len(info.levels[0].vertices) / 3
    assert set(info.stage_seconds) == {"hierarchy", "field", "level 1", "level 0"}
    # without a density the mesh's own vertices are coloured
    own = synthesize_surface(s, ex, schedule=SurfaceSchedule(levels=1), rng=0)
    assert np.array_equal(own.vertices, s.vertices)


def test_queries_hold_exemplar_colours_not_blends():
    # Each grid point reads one vertex (Wei & Levoy and Turk copy colours, they never average them): every row
    # of the resampling matrix is a single 1. The blended resampling of the first version (a Gaussian-weighted
    # mean of the 4 nearest vertices) made queries softer than any exemplar neighbourhood: mortar lines and
    # paving cracks melted into the stones, and in the sweep order the blends grew into streaks.
    from texsynth.surface._vertex_synthesis import SurfaceFrame, grid_offsets, resample_grid, resampling_matrix
    s = sphere(642)
    frame = SurfaceFrame(s, tangent_field(s, rng=0), 0.1)
    vertex, valid = resample_grid(frame, frame, grid_offsets((5, 5)), 0.1)
    assert valid.all() and vertex.shape == (642, 25)
    assert np.array_equal(vertex[:, 12], np.arange(642))  # the centre point reads the vertex itself
    matrix = resampling_matrix(vertex, valid, 642)
    assert np.array_equal(matrix.getnnz(axis=1), np.ones(matrix.shape[0])) and np.allclose(matrix.data, 1)
    # a point off an open surface's edge reads nothing
    cut = valid.copy()
    cut[0, :5] = False
    assert resampling_matrix(vertex, cut, 642)[:5].nnz == 0


def test_paper_preset_and_global_search_run():
    ex = load("bread")[:32, :32]
    out, info = synthesize_surface(sphere(162), ex, n_vertices=500, schedule=TWO, preset="paper", rng=0,
                                   return_info=True)
    # the sweep's causal queries weigh their grid points each their own way: an exact search, not the TSVQ
    assert info.candidates == "all" and info.order == "sweep" and info.method == "exact"
    assert out.colors.shape == (len(out.vertices), 3)
    _, info = synthesize_surface(sphere(162), ex, n_vertices=500, preset="paper", rng=0, return_info=True,
                                 schedule=SurfaceSchedule(levels=2, order="independent"))
    assert info.method == "tsvq"


# ---------------------------------------------------------------------------- Turk's sweep order
def _flat_square(n=30):
    """The unit square in the z = 0 plane, facing +z."""
    y, x = np.mgrid[0:n, 0:n] / (n - 1)
    vertices = np.stack([x.ravel(), -y.ravel(), np.zeros(n * n)], axis=1)
    i = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
    return vertices, np.concatenate([np.stack([i, i + n, i + n + 1], 1), np.stack([i, i + n + 1, i + 1], 1)])


def test_sweep_distance_scans_the_rows_downwards():
    from texsynth.surface._meshio import as_mesh
    from texsynth.surface._vertex_synthesis import SurfaceFrame, _sweep_distance

    # a flat square with the field along x: the exemplar's rows run along x and go down along -y, so the sweep
    # distance is the height measured downwards, in vertex spacings (exactly: the field has a potential)
    square = retile(as_mesh(_flat_square()), 3000, rng=0)
    t = np.tile([1.0, 0, 0], (len(square.vertices), 1))
    spacing = 1 / 50
    s = _sweep_distance(SurfaceFrame(square, t, spacing), 1)
    assert np.corrcoef(s, -square.vertices[:, 1])[0, 1] > 0.999
    assert abs((s.max() - s.min()) * spacing - np.ptp(square.vertices[:, 1])) < 0.01
    # a texture with 2- or 4-fold symmetry may have its field turned by a half or a quarter turn between
    # neighbours: a sweep down the rows (either way: the texture looks the same turned by a half turn, and with
    # 4-fold symmetry rows and columns are alike), once each neighbour's turn is undone (without that, the
    # half-turned field below gave a sweep correlating 0.35 with the height)
    rng = np.random.default_rng(0)
    turned = t.copy()
    turned[rng.random(len(t)) < 0.5] *= -1
    height, across = -square.vertices[:, 1], square.vertices[:, 0]
    assert np.corrcoef(_sweep_distance(SurfaceFrame(square, turned, spacing), 2), height)[0, 1] ** 2 > 0.998
    quarter = rng.random(len(t)) < 0.5
    turned[quarter] = np.cross([0, 0, 1.0], turned[quarter])
    s4 = _sweep_distance(SurfaceFrame(square, turned, spacing), 4)
    assert max(np.corrcoef(s4, height)[0, 1] ** 2, np.corrcoef(s4, across)[0, 1] ** 2) > 0.998
    # on a sphere with the field along the latitudes the sweep runs from pole to pole
    ball = sphere(2562)
    lat = tangent_field(ball, lambda p: np.cross([0, 0, 1.0], p))
    assert abs(np.corrcoef(_sweep_distance(SurfaceFrame(ball, lat, 0.05), 1), ball.vertices[:, 2])[0, 1]) > 0.99


def test_sweep_queries_see_only_the_vertices_already_visited():
    from texsynth.surface._vertex_synthesis import (ExemplarLevel, SurfaceFrame, grid_offsets, resample_grid,
                                                    _sweep_distance, _sweep_level)
    from texsynth.core._progress import Progress

    ball = sphere(642)
    frame = SurfaceFrame(ball, tangent_field(ball, lambda p: np.cross([0, 0, 1.0], p)), 0.1)
    ex = ExemplarLevel(load("bread")[:24, :24], None, (5, 5), (3, 3), 0.5)
    vertex, valid = resample_grid(frame, frame, grid_offsets((5, 5)), 0.1)
    sweep = _sweep_distance(frame, 1)
    rank = np.empty(len(sweep), dtype=int)
    rank[np.argsort(sweep, kind="stable")] = np.arange(len(sweep))
    seen = []

    def search(group, vectors, weights, sources, rng):
        seen.append((group[0], weights[0].reshape(25, 3)[:, 0] > 0))
        return np.array([0]), np.array([0.0])

    with Progress(False, 2, "test") as bar:
        _sweep_level(ex, vertex, None, np.repeat(valid, 3, axis=1) * ex.weights, np.zeros(len(sweep), int),
                     search, 2, sweep, np.random.default_rng(0), bar, 0)
    n = len(sweep)
    order = list(np.argsort(sweep, kind="stable"))
    first = [v for v, _ in seen if v == order[0]]
    # one at a time, by the sweep; the first vertex sees nothing and keeps its start (no search) in the first pass
    assert [v for v, _ in seen[:n - 1]] == order[1:] and len(first) == 1
    for v, counted in seen[:n - 1]:
        assert np.array_equal(counted, valid[v] & (rank[vertex[v]] < rank[v]))  # the causal part only
    # about half of a 5 x 5 neighbourhood lies behind the sweep (12 of 25 points in a scanline)
    assert 0.4 < np.mean([c.mean() for _, c in seen[:n - 1]]) < 0.6
    for v, counted in seen[n - 1:]:  # a second pass sees every vertex
        assert np.array_equal(counted, valid[v])


SWEEP = SurfaceSchedule(levels=2, order="sweep")


def test_sweep_order_copies_exemplar_pixels_and_is_the_paper_preset():
    ex = load("bread")[:40, :40]
    s = sphere(162)
    a, info = synthesize_surface(s, ex, n_vertices=800, schedule=SWEEP, rng=3, return_info=True)
    assert info.order == "sweep"
    assert np.array_equal(a.colors, synthesize_surface(s, ex, n_vertices=800, schedule=SWEEP, rng=3).colors)
    assert np.allclose(a.colors, ex[info.sources[:, 0], info.sources[:, 1]], atol=1e-6)
    _, paper = synthesize_surface(s, ex[:32, :32], n_vertices=500, schedule=TWO, preset="paper", rng=0,
                                  return_info=True)
    assert paper.order == "sweep"


def test_sweep_memory_is_checked_before_anything_is_allocated(monkeypatch):
    # the sweep distance's sparse solve is counted in the memory check (made huge here, so only it can fail)
    monkeypatch.setattr("texsynth.surface._vertex_synthesis._SWEEP_BYTES", 10**12)
    ex = load("bread")[:40, :40]
    with pytest.raises(ValueError, match="n_vertices=800 needs about .* GiB"):
        synthesize_surface(sphere(162), ex, n_vertices=800, schedule=SWEEP)
    assert synthesize_surface(sphere(162), ex, n_vertices=800, schedule=TWO).colors is not None


def test_synthesis_bad_input():
    s = sphere(162)
    ex = load("bread")[:32, :32]
    with pytest.raises(ValueError, match=r"field must be one \(x, y, z\) vector per vertex, shape \(162, 3\)"):
        synthesize_surface(s, ex, field=np.ones((5, 3)), schedule=TWO)
    with pytest.raises(ValueError, match="field has 162 vectors with NaN"):
        synthesize_surface(s, ex, field=np.full((162, 3), np.nan), schedule=TWO)
    with pytest.raises(ValueError, match="n_vertices=.* needs about .* GiB .* pass a smaller n_vertices"):
        synthesize_surface(s, ex, n_vertices=10**12, schedule=TWO)
    with pytest.raises(ValueError, match="pixel_size=1e-09 .* pass a larger pixel_size"):
        synthesize_surface(s, ex, pixel_size=1e-9, schedule=TWO)
    with pytest.raises(ValueError, match="pass exactly one of n_vertices"):
        synthesize_surface(s, ex, n_vertices=100, pixel_size=0.1, schedule=TWO)
    with pytest.raises(ValueError, match="coarsest level"):
        synthesize_surface(s, ex, schedule=SurfaceSchedule(levels=3))
    with pytest.raises(ValueError, match="candidates must be one of"):
        synthesize_surface(s, ex, search=Search(candidates="some"), schedule=TWO)
    with pytest.raises(ValueError, match="order must be one of 'independent', 'sweep', got 'scanline'"):
        synthesize_surface(s, ex, schedule=SurfaceSchedule(levels=2, order="scanline"))
    with pytest.raises(ValueError, match="preset must be one of"):
        synthesize_surface(s, ex, preset="fast", schedule=TWO)
    with pytest.raises(TypeError, match="schedule must be a"):
        synthesize_surface(s, ex, schedule={"levels": 2})
    with pytest.raises(ValueError, match="passes must be"):
        synthesize_surface(s, ex, schedule=SurfaceSchedule(levels=2, passes=0))


def test_a_mesh_of_pieces_smaller_than_the_spacing_is_refused_by_name():
    """300 specks, each far smaller than the vertex spacing: retiled vertices on no face would give no frame."""
    from texsynth.surface import Mesh

    speck = sphere(42)
    centers = np.random.default_rng(0).uniform(-3, 3, (300, 3))
    vertices = np.concatenate([speck.vertices * 0.05 + c for c in centers])
    faces = np.concatenate([speck.faces + i * len(speck.vertices) for i in range(300)])
    with pytest.raises(ValueError, match="mesh: .* lie on no face .*n_vertices"):
        synthesize_surface(Mesh(vertices, faces), load("bread")[:48, :48], n_vertices=600, rng=0)
