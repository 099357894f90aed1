"""Patch-based sampling (Liang et al. 2001): speed beside quilting and patchwork, its zone search, and pixel synthesis.

Run: nice -n 10 python benchmarks/bench_patch_sampling.py [--repeat 2]   (from the repository root)

Target (issue 17): patch-based sampling 256x256 -> 1024x1024 colour in at most 3 s, as quilting.

Side by side, in the same run:
- image quilting and ``patchwork`` (grid 64) on the same inputs: the table of ``benchmarks/bench_quilting.py``;
- the overlap errors of every exemplar block by FFT (core.search.WindowSearch) against the search layer's
  PatchIndex over the boundary-zone vectors (exact and kd-tree: Liang et al.'s kind of acceleration);
- patch-based sampling against Wei-Levoy pixel synthesis (the lecture's "orders of magnitude faster").

The figures of docs/methods/patch_sampling.md come from ``python benchmarks/bench_quilting.py --figures``.
"""

import argparse

import numpy as np

from bench_quilting import PHOTOS, TEXTURES, best_of, load, speed


def template_search(repeat):
    from texsynth.core.search import PatchIndex
    from texsynth.core.search._template import WindowSearch

    ex = load(PHOTOS / "cobblestones_1.png", 128)
    B, E = 32, 5
    known = np.zeros((B, B), bool)
    known[:, :E] = known[:E, :] = True  # the L-shaped zone of Liang et al. / quilting's corner case
    rng = np.random.default_rng(1)
    queries = [ex[r:r + B, c:c + B] + rng.normal(0, 0.02, (B, B, 3))
               for r, c in rng.integers(0, ex.shape[0] - B, (50, 2))]
    print(f"\nOverlap errors of every block: 128 px colour exemplar, {B} px blocks, L-shaped zone {E} px "
          f"({int(known.sum()) * 3}-D), 50 queries, best of {repeat}")
    t_build, search = best_of(lambda: WindowSearch(ex, (B, B)), repeat)
    t_query, maps = best_of(lambda: [search.sq_distances(q, known) for q in queries], repeat)
    truth = np.array([int(np.argmin(m)) for m in maps])
    print(f"  FFT (WindowSearch): build {t_build:.3f} s, 50 queries {t_query:.3f} s: every block's exact error")
    from texsynth.core.neighborhood import all_patches

    vectors = all_patches(ex.astype(np.float32), (B, B))[:, :, known].reshape(-1, int(known.sum()) * 3)
    q = np.stack([qq[known] for qq in queries]).reshape(len(queries), -1).astype(np.float32)
    for method in ("exact", "kdtree"):
        t_index, index = best_of(PatchIndex, repeat, vectors, method=method, rng=0)
        t_q, (idx, _) = best_of(index.query, repeat, q, k=16)
        recall = np.mean(idx[:, 0] == truth)
        print(f"  PatchIndex({method!r}) over the zone vectors ({vectors.nbytes / 2**20:.0f} MiB): build "
              f"{t_index:.3f} s, 50 queries (k = 16) {t_q:.3f} s, recall@1 {recall:.2f}; gives 16 candidates, "
              f"not every block's error")


def pixels_against_patches(repeat):
    import texsynth
    from texsynth.patch._patch_sampling import patch_sampling

    ex = load(TEXTURES / "lcv" / "text.pgm", 128)
    t_pix, _ = best_of(lambda: texsynth.synthesize_pixels(ex, 256, rng=0), 1)
    t_ps, _ = best_of(lambda: patch_sampling(ex, 256, block=32, rng=0), repeat)
    print(f"\nPatch-based sampling against pixel synthesis, text 128 -> 256 grey: patch sampling {t_ps:.3f} s, "
          f"Wei-Levoy (scanline, 3 levels) {t_pix:.2f} s: {t_pix / t_ps:.0f}x")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    speed(args.repeat)
    template_search(args.repeat)
    pixels_against_patches(args.repeat)


if __name__ == "__main__":
    main()
