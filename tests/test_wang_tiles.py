"""Wang tiles (texsynth.patch._wang_tiles): the tile set, its edges pixel for pixel, and the stochastic tiling."""

from pathlib import Path

import numpy as np
import pytest

from conftest import load_texture
from texsynth.patch._wang_tiles import (
    EAST,
    NORTH,
    SOUTH,
    WEST,
    WangTileSet,
    tile_edges,
    wang_texture,
    wang_tiles,
    wang_tiling,
)

PHOTOS = Path(__file__).resolve().parents[1] / "benchmarks" / "photos"  # committed with the repository


def photo(name, size=128):
    from texsynth.io import load_image

    path = PHOTOS / f"{name}.png"
    if not path.exists():
        pytest.skip(f"{path} is absent")
    image = load_image(path)
    return np.ascontiguousarray(image[:size, :size, :3])


def natural_jump(exemplar):
    """The exemplar's own mean squared difference between 4-neighbours: its gradient energy per pair."""
    e = exemplar if exemplar.ndim == 3 else exemplar[..., None]
    return np.concatenate([((e[1:] - e[:-1]) ** 2).sum(-1).ravel(), ((e[:, 1:] - e[:, :-1]) ** 2).sum(-1).ravel()]).mean()


def cut_visibility(tiles, labels, exemplar):
    """The mean squared jump between neighbours inside the tiles that come from different diamonds (the cuts),
    over the exemplar's own: 1 means the cuts are as smooth as the texture."""
    t = tiles.tiles if tiles.tiles.ndim == 4 else tiles.tiles[..., None]
    jumps = []
    for axis in (1, 2):
        a, b = [slice(None)] * 3, [slice(None)] * 3
        a[axis], b[axis] = slice(None, -1), slice(1, None)
        differ = labels[tuple(a)] != labels[tuple(b)]
        jumps.append(((t[tuple(a)] - t[tuple(b)]) ** 2).sum(-1)[differ])
    return np.concatenate(jumps).mean() / natural_jump(exemplar)


def edge_jumps(image, T, band=3):
    """Mean squared jump across the tile boundaries of a tiling (corner pixels left out), and between the
    neighbouring pairs of rows (columns) within ``band`` pixels of a boundary inside the tiles."""
    o = image if image.ndim == 3 else image[..., None]
    d_rows = ((o[1:] - o[:-1]) ** 2).sum(-1)  # between rows i and i + 1
    d_cols = ((o[:, 1:] - o[:, :-1]) ** 2).sum(-1)
    pos_r, pos_c = np.arange(1, o.shape[0]) % T, np.arange(1, o.shape[1]) % T  # 0: a pair across a boundary
    near_r = (np.minimum(pos_r, T - pos_r) <= band) & (pos_r != 0)
    near_c = (np.minimum(pos_c, T - pos_c) <= band) & (pos_c != 0)
    not_corner_c = (np.arange(o.shape[1]) % T != 0) & (np.arange(o.shape[1]) % T != T - 1)
    not_corner_r = (np.arange(o.shape[0]) % T != 0) & (np.arange(o.shape[0]) % T != T - 1)
    across = np.concatenate([d_rows[pos_r == 0][:, not_corner_c].ravel(), d_cols[:, pos_c == 0][not_corner_r].ravel()])
    near = np.concatenate([d_rows[near_r][:, not_corner_c].ravel(), d_cols[:, near_c][not_corner_r].ravel()])
    return across.mean(), near.mean()


# --------------------------------------------------------------------------- the tile set


@pytest.mark.parametrize("colors", [2, 3])
def test_a_complete_set_two_tiles_for_every_north_west_pair(colors):
    edges = tile_edges(colors)
    assert edges.shape == (2 * colors**2, 4) and len({tuple(e) for e in edges}) == len(edges)
    for n in range(colors):
        for w in range(colors):
            pair = edges[(edges[:, NORTH] == n) & (edges[:, WEST] == w)]
            assert len(pair) == 2
            assert pair[0, SOUTH] != pair[1, SOUTH] and pair[0, EAST] != pair[1, EAST]
    # every (south, east) pair used equally often: no colour is favoured by the tiling
    _, counts = np.unique(edges[:, [SOUTH, EAST]], axis=0, return_counts=True)
    assert len(counts) == colors**2 and np.all(counts == 2)


def test_edges_are_their_colour_samples_pixel_for_pixel_and_every_pixel_is_a_diamond_copy():
    ex = photo("bricks_1", 256)
    tiles, info = wang_tiles(ex, 128, rng=3, return_info=True)
    assert tiles.tiles.shape == (8, 128, 128, 3) and len(tiles) == 8 and tiles.tile == 128
    T, m = 128, info.overlap // 2
    a = T // 2 + m + 1
    (hr, hc), (vr, vc) = info.samples[0].T, info.samples[1].T
    for i, (n, e, s, w) in enumerate(tiles.edges):
        t = tiles.tiles[i]
        # the paper's construction: every edge pixel but the corners comes from its edge's diamond, so two tiles
        # that share a colour meet along two adjacent rows (columns) of the same exemplar sample
        assert np.array_equal(t[0, :-1], ex[hr[n] + a, hc[n]:hc[n] + T - 1])
        assert np.array_equal(t[-1, :-1], ex[hr[s] + a - 1, hc[s]:hc[s] + T - 1])
        assert np.array_equal(t[1:-1, 0], ex[vr[w] + 1:vr[w] + T - 1, vc[w] + a])
        assert np.array_equal(t[:, -1], ex[vr[e]:vr[e] + T, vc[e] + a - 1])
        # and every pixel is a copy of the exemplar pixel of its label's sample
        lab = info.labels[i]
        y, x = np.mgrid[:T, :T]
        src_r = np.select([lab == NORTH, lab == SOUTH, lab == WEST, lab == EAST],
                          [hr[n] + a + y, hr[s] + y - T + a, vr[w] + y, vr[e] + y])
        src_c = np.select([lab == NORTH, lab == SOUTH, lab == WEST, lab == EAST],
                          [hc[n] + x, hc[s] + x, vc[w] + a + x, vc[e] + x - T + a])
        assert np.array_equal(t, ex[src_r, src_c])
        # each diamond keeps to its side: north on top, east on the right ...
        assert lab[5, T // 2] == NORTH and lab[T // 2, -5] == EAST and lab[-5, T // 2] == SOUTH and lab[T // 2, 4] == WEST
    # tiles that share a colour have identical edges there
    for c in range(2):
        bottoms = tiles.tiles[tiles.edges[:, SOUTH] == c, -1, :-1]
        assert all(np.array_equal(bottoms[0], b) for b in bottoms)


def test_matched_samples_of_a_periodic_exemplar_make_a_seamless_periodic_tiling():
    # samples chosen within quilting's tolerance of each other land on one lattice: every cut costs nothing and
    # the tiling is the exemplar's own periodic pattern; random samples (error_tolerance=None) do not
    motif = (np.random.default_rng(0).random((16, 16, 3)) * 255).astype(np.uint8)
    ex = np.tile(motif, (12, 12, 1))
    tiles, info = wang_tiles(ex, 64, rng=2, return_info=True)
    assert info.seam_costs.max() == 0.0
    assert len({tuple(p) for p in info.samples.reshape(-1, 2) % 16}) <= 2  # one phase per sample shape
    out = wang_tiling(tiles, 320, rng=0)
    assert np.array_equal(out, np.roll(out, 16, axis=0)[:320]) and np.array_equal(out, np.roll(out, 16, axis=1))
    _, random_info = wang_tiles(ex, 64, error_tolerance=None, rng=2, return_info=True)
    assert random_info.seam_costs.max() > 0


def test_the_cuts_hide_the_joins_against_random_samples_joined_straight():
    # Seam visibility: the mean squared jump between neighbours from different diamonds over the exemplar's own
    # mean squared neighbour difference (1 = as smooth as the texture). The baseline is the same construction
    # without the paper's seams: random samples joined along the straight diagonals (what a tile set looks
    # like with no quilting), measured at 3.0-3.9 (bricks), 4.7-6.4 (bread), 7.2-8.3 (gravel), 2.1-3.5 (moss)
    # over seeds 0-2, against 1.9-2.1, 2.0-2.4, 2.2-2.5 and 1.2-1.3 with the cuts. A wrong cut (through the
    # middle of the band, or on the wrong pair of diamonds) lands near the baseline, so the cut must stay
    # below three quarters of it on every texture and seed, and below 3.5 times the texture's own jumps.
    for name, ex in (("bricks", photo("bricks_1")), ("bread", load_texture("jcjohnson/bread.png", 128)),
                     ("gravel", load_texture("skimage/gravel.png", 128)), ("moss", photo("moss_1"))):
        for seed in range(2):
            tiles, info = wang_tiles(ex, 64, rng=seed, return_info=True)
            base, base_info = wang_tiles(ex, 64, cut=False, error_tolerance=None, rng=seed, return_info=True)
            ours, baseline = cut_visibility(tiles, info.labels, ex), cut_visibility(base, base_info.labels, ex)
            assert ours < 0.75 * baseline and ours < 3.5, (name, seed, ours, baseline)


# --------------------------------------------------------------------------- the tiling


def test_the_tiling_keeps_every_edge_constraint_and_is_made_of_the_tiles():
    tiles = wang_tiles(load_texture("jcjohnson/bread.png", 128), 40, rng=0)
    out, info = wang_tiling(tiles, (230, 310), rng=5, return_info=True)
    idx, e = info.indices, tiles.edges
    assert out.shape == (230, 310, 3) and idx.shape == (6, 8)
    assert np.array_equal(e[idx[:-1], SOUTH], e[idx[1:], NORTH])
    assert np.array_equal(e[idx[:, :-1], EAST], e[idx[:, 1:], WEST])
    for r in range(6):
        for c in range(8):
            block = out[40 * r:40 * r + 40, 40 * c:40 * c + 40]
            assert np.array_equal(block, tiles.tiles[idx[r, c], :block.shape[0], :block.shape[1]])
    # stochastic: every tile is used, the same seed repeats, another seed differs
    _, big_info = wang_tiling(tiles, 800, rng=1, return_info=True)
    assert set(np.unique(big_info.indices)) == set(range(8))
    assert np.array_equal(wang_tiling(tiles, (230, 310), rng=5), out)
    assert not np.array_equal(wang_tiling(tiles, (230, 310), rng=6), out)


def test_tilings_are_seamless_across_tile_edges():
    # Gradient energy across the tile edges against inside the tiles near them (the rows and columns within 3
    # pixels of an edge). Across an edge the two pixels are neighbours in one exemplar sample, so the ratio is the
    # texture's own variation from row to row: measured 0.5-0.9 over seeds 0-2 on bricks (the mortar lines make it
    # vary; 0.4-1.9 with one set of samples instead of the best of 8), 0.7-1.2 on gravel and cobblestones. The baseline, random exemplar blocks tiled side by side (no
    # colours, no seams), measured 3.0-8.0. The threshold 2.4 lies between the two (their geometric mean).
    for ex in (photo("bricks_1", 256), load_texture("skimage/gravel.png", 256), photo("cobblestones_1", 256)):
        for seed in range(2):
            out = wang_texture(ex, 1024, tile=96, rng=seed)
            across, inside = edge_jumps(out, 96)
            gen = np.random.default_rng(seed)
            blocks = [ex[r:r + 96, c:c + 96] for r, c in gen.integers(0, 256 - 96, (8, 2))]
            random_tiles = WangTileSet(tiles=np.stack(blocks), edges=np.zeros((8, 4), int), colors=1)
            r_across, r_inside = edge_jumps(wang_tiling(random_tiles, 1024, rng=0), 96)
            assert across / inside < 2.4 < r_across / r_inside, (across / inside, r_across / r_inside)


# --------------------------------------------------------------------------- conventions and bad input


def test_layout_dtype_colours_and_determinism():
    grey = load_texture("lcv/metal.pgm", 96)
    tiles = wang_tiles(grey, 32, colors=3, rng=0)
    assert tiles.tiles.shape == (18, 32, 32) and tiles.colors == 3
    out = wang_tiling(tiles, 100, rng=0)
    assert out.shape == (100, 100)
    f32 = load_texture("jcjohnson/bread.png", 96).astype(np.float32)
    assert wang_texture(f32, 64, tile=32, rng=0).dtype == np.float32
    a = wang_texture(grey, 80, tile=32, rng=7)
    assert np.array_equal(a, wang_texture(grey, 80, tile=32, rng=7))
    out, info = wang_texture(grey, 80, tile=32, rng=7, return_info=True)
    assert np.array_equal(out, a) and set(info.stage_seconds) == {"tiles", "choice", "assembly"}
    random_samples = wang_tiles(grey, 32, error_tolerance=None, overlap=0, rng=0)
    assert random_samples.tiles.shape == (8, 32, 32)


@pytest.mark.parametrize("call, error, words", [
    (lambda ex: wang_tiles(ex, 95), ValueError, "tile"),
    (lambda ex: wang_tiles(ex, 32, colors=1), ValueError, "colors"),
    (lambda ex: wang_tiles(ex, 32, overlap=20), ValueError, "overlap"),
    (lambda ex: wang_tiles(ex, 32, error_tolerance=-1), ValueError, "error_tolerance"),
    (lambda ex: wang_tiles(ex, 32, cut="yes"), TypeError, "cut"),
    (lambda ex: wang_tiles(ex[:6, :6]), ValueError, "exemplar"),
    (lambda ex: wang_tiling(ex, 100), TypeError, "tiles"),
    (lambda ex: wang_tiling(wang_tiles(ex, 32, rng=0), (10**6, 10**6)), ValueError, "size"),
    (lambda ex: wang_tiling(WangTileSet(np.zeros((1, 8, 8)), np.array([[0, 1, 1, 0]]), 2), 40), ValueError,
     "tiles has no tile"),
])
def test_bad_input_names_the_parameter(call, error, words):
    with pytest.raises(error, match=words):
        call(load_texture("jcjohnson/bread.png", 96))
