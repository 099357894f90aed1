"""k-coherent candidates (texsynth.core.search._coherent) against brute force on tiny cases."""

import numpy as np
import pytest

from texsynth.core.search._coherent import COHERENT_MODES, KCoherence, neighbor_sources


def _brute_sets(vectors, shape, k, min_distance=0):
    """Reference: every pair's distance, position x first, then the others by (distance, index)."""
    d2 = ((vectors[:, None, :] - vectors[None, :, :]) ** 2).sum(-1)
    rows, cols = np.divmod(np.arange(len(vectors)), shape[1])
    sets = []
    for x in range(len(vectors)):
        far = np.maximum(abs(rows - rows[x]), abs(cols - cols[x])) >= min_distance
        others = [y for y in np.lexsort((np.arange(len(vectors)), d2[x])) if y != x]
        # members far enough from x first, then (if too few) the nearest of the rest
        ranked = [y for y in others if far[y]] + [y for y in others if not far[y]]
        sets.append([x] + ranked[: k - 1])
    return np.array(sets)


@pytest.mark.parametrize("k, min_distance", [(1, 0), (2, 0), (4, 0), (3, 2), (5, 3)])
def test_sets_equal_brute_force(k, min_distance):
    rng = np.random.default_rng(k + 10 * min_distance)
    shape = (5, 7)
    vectors = rng.random((35, 6))
    kc = KCoherence(vectors, shape, k, min_distance=min_distance, method="exact")
    np.testing.assert_array_equal(kc.sets, _brute_sets(vectors, shape, k, min_distance))


def test_sets_start_with_the_position_even_among_duplicates():
    # every vector equal: ties go to the lowest index, yet each set starts with its own position
    kc = KCoherence(np.zeros((12, 3)), (3, 4), k=3, method="exact")
    np.testing.assert_array_equal(kc.sets[:, 0], np.arange(12))
    assert all(len(set(row)) == 3 for row in kc.sets.tolist())


def test_kdtree_sets_are_close_to_exact():
    # an approximate backend may miss a member, but every member is a real position and x comes first
    rng = np.random.default_rng(0)
    vectors = np.repeat(rng.random((150, 8)), 2, axis=0) + 1e-3 * rng.random((300, 8))
    exact = KCoherence(vectors, (15, 20), 2, method="exact").sets
    approx = KCoherence(vectors, (15, 20), 2, method="kdtree", rng=0).sets
    np.testing.assert_array_equal(approx[:, 0], np.arange(300))
    assert (approx[:, 1] == exact[:, 1]).mean() > 0.9


def _brute_candidates(kc, sources, offsets, mode):
    rows_n, cols_n = kc.shape
    out = []
    for src_row, off in zip(sources, np.broadcast_to(offsets, (len(sources),) + np.shape(offsets)[-2:])):
        cand = []
        for s, (dy, dx) in zip(src_row, off):
            r, c = divmod(int(s), cols_n)
            r, c = r - dy, c - dx  # Ashikhmin: s(p + d) - d
            if mode == "nearest":
                r, c = min(max(r, 0), rows_n - 1), min(max(c, 0), cols_n - 1)
            elif mode == "wrap":
                r, c = r % rows_n, c % cols_n
            else:  # reflect
                r = -r if r < 0 else 2 * (rows_n - 1) - r if r >= rows_n else r
                c = -c if c < 0 else 2 * (cols_n - 1) - c if c >= cols_n else c
            cand.extend(kc.sets[r * cols_n + c])
        out.append(cand)
    return np.array(out)


@pytest.mark.parametrize("mode", ["nearest", "wrap", "reflect"])
@pytest.mark.parametrize("k", [1, 3])
def test_candidates_equal_brute_force(mode, k):
    rng = np.random.default_rng(k)
    shape = (6, 5)
    kc = KCoherence(rng.random((30, 4)), shape, k, method="exact")
    sources = rng.integers(0, 30, size=(40, 4))
    offsets = np.array([[-1, -1], [-1, 2], [0, -1], [3, 0]])
    got = kc.candidates(sources, offsets, mode=mode)
    assert got.shape == (40, 4 * k)
    np.testing.assert_array_equal(got, _brute_candidates(kc, sources, offsets, mode))
    per_query = rng.integers(-3, 4, size=(40, 4, 2))  # offsets may differ per query
    np.testing.assert_array_equal(kc.candidates(sources, per_query, mode=mode),
                                  _brute_candidates(kc, sources, per_query, mode))


def test_random_mode_redraws_only_what_leaves_the_grid():
    kc = KCoherence(None, (10, 10), 1)
    sources = np.array([[55, 0, 99]])
    offsets = np.array([[0, 1], [0, 1], [-1, 0]])  # 55 -> (5, 4) inside; 0 -> (0, -1) and 99 -> (10, 9) leave
    draws = np.array([kc.candidates(sources, offsets, rng=seed)[0] for seed in range(200)])
    assert (draws[:, 0] == 54).all()
    assert len(np.unique(draws[:, 1])) > 50 and len(np.unique(draws[:, 2])) > 50  # random cells, not the edge
    np.testing.assert_array_equal(kc.candidates(sources, offsets, rng=3), kc.candidates(sources, offsets, rng=3))


def test_neighbor_sources_wrap_around_the_output():
    field = np.arange(20).reshape(4, 5)
    got = neighbor_sources(field, [[0, 0], [3, 4]], [[-1, -1], [0, 1], [1, 0]])
    np.testing.assert_array_equal(got, [[19, 1, 5], [13, 15, 4]])


def test_bad_input():
    v = np.zeros((6, 2))
    with pytest.raises(ValueError, match="shape"):
        KCoherence(v, (2, 4), 2)
    with pytest.raises(ValueError, match="k=7"):
        KCoherence(v, (2, 3), 7)
    with pytest.raises(ValueError, match="min_distance"):
        KCoherence(v, (2, 3), 2, min_distance=-1)
    with pytest.raises(TypeError, match="shape"):
        KCoherence(v, 6, 2)
    kc = KCoherence(v, (2, 3), 2)
    with pytest.raises(ValueError, match="grid cells 0..5"):
        kc.candidates([[6]], [[0, 0]])
    with pytest.raises(ValueError, match="offsets"):
        kc.candidates([[1, 2]], [[0, 0]])
    with pytest.raises(ValueError, match="mode"):
        kc.candidates([[1]], [[0, 0]], mode="clip")
    assert set(COHERENT_MODES) >= {"random", "nearest", "wrap", "reflect"}


# --------------------------------------------------------------------------- texture optimization's M-step
def test_optimization_m_step_offers_the_sets_after_the_first_search(texture, monkeypatch):
    """Every M-step but the synthesis's first (from random neighbourhoods) searches over the stage's
    k-coherence sets, with no random search; the energy still never rises within a stage."""
    import texsynth
    import texsynth.core.em._mstep as mstep  # where the field M-step looks the search up
    from texsynth.core.search import _patchmatch as pm
    from texsynth.optimization import Search, Terms

    calls = []
    checked = mstep.patchmatch_features

    def spy(*args, sets=None, **kwargs):
        calls.append(sets)
        return checked(*args, sets=sets, **kwargs)

    random_searches = []
    search = pm._Problem.random_search
    monkeypatch.setattr(mstep, "patchmatch_features", spy)
    monkeypatch.setattr(pm._Problem, "random_search",
                        lambda self, *a: (random_searches.append(self.sets is None), search(self, *a))[1])
    ex = texture("jcjohnson/bread.png", 64)
    out, info = texsynth.optimize_texture(ex, 96, search=Search(candidates="k-coherent", k=3),
                                          terms=Terms(copy_limit=None, completeness_weight=0, histogram_matching=False),
                                          rng=0, return_info=True)
    assert out.shape == (96, 96, 3) and calls[0] is None and all(s is not None for s in calls[1:])
    for sets in calls[1:]:
        assert sets.shape[1] == 3 and np.array_equal(sets[:, 0], np.arange(len(sets)))
    assert any(random_searches) and not all(random_searches)  # the first search only
    for s in range(len(info.stages)):
        e = info.energy[info.stage == s]
        assert np.all(np.diff(e) <= 1e-9 * e[0])


def test_optimization_k_coherent_is_deterministic_and_differs_by_k(texture):
    import texsynth
    from texsynth.optimization import Search

    ex = texture("jcjohnson/bread.png", 48)
    a = texsynth.optimize_texture(ex, 64, search=Search(candidates="k-coherent"), rng=1)
    np.testing.assert_array_equal(a, texsynth.optimize_texture(ex, 64, search=Search(candidates="k-coherent"), rng=1))
    assert not np.array_equal(a, texsynth.optimize_texture(ex, 64, search=Search(candidates="k-coherent", k=1), rng=1))
    assert not np.array_equal(a, texsynth.optimize_texture(ex, 64, rng=1))


@pytest.mark.parametrize("kwargs, match", [
    ({"search": {"candidates": "coherent"}}, "candidates must be one of 'all', 'k-coherent'"),
    ({"search": {"candidates": "k-coherent", "k": 0}}, "k must be"),
    ({"search": {"candidates": "k-coherent", "k": 2.5}}, "k must be"),
    ({"search": {"candidates": "k-coherent"}, "terms": {"gradient_weight": 1.0}},
     "does not combine with gradient_weight"),
    ({"search": {"candidates": "k-coherent"}, "preset": "paper"}, "does not combine with preset='paper'"),
    ({"search": {"candidates": "k-coherent", "method": "exact"}}, "does not combine with method='exact'"),
    ({"search": {"candidates": "k-coherent"},
      "constraints": {"mask": np.ones((40, 40)), "target": np.zeros((40, 40, 3)), "constraint_weight": 10.0}},
     "does not combine with soft constraints"),
])
def test_optimization_k_coherent_bad_options(texture, kwargs, match):
    import texsynth
    from texsynth.optimization import Constraints, Search, Terms

    groups = {"search": Search, "terms": Terms, "constraints": Constraints}
    with pytest.raises((ValueError, TypeError), match=match):  # a group may refuse a field as it is made
        kwargs = {name: groups[name](**value) if name in groups else value for name, value in kwargs.items()}
        texsynth.optimize_texture(texture("jcjohnson/bread.png", 32), 40, **kwargs)
