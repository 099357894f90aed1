"""scikit-learn and scikit-image against texsynth's hand-written routines, side by side in one run.

For each routine the library wrote itself, the named package's routine that
does the same job is timed on the same real data in the same process, and its
answer is compared with an exact reference:

- TSVQ's k-means per tree node (``core.search._tsvq._lloyd``) against
  scikit-learn's ``KMeans`` and ``MiniBatchKMeans``: tree build time, query
  time, recall@1 and distance ratio of the whole TSVQ search against exact
  search;
- the colour PCA of the statistical methods (``core.color.color_pca``: the
  3 x 3 covariance and ``numpy.linalg.eigh``) against ``sklearn.decomposition.PCA``
  (``svd_solver="covariance_eigh"`` and ``"full"``) on the pixels of 256 and 400 px
  photographs (the exemplar sizes of Heeger-Bergen, Portilla-Simoncelli and tiling
  and blending): time, and the angle between the two first axes;
- the kd-tree's PCA (``core.search._kdtree.pca``: scatter matrix up to 256-D,
  randomized subspace iteration above) against ``sklearn.utils.extmath.
  randomized_svd`` and ``sklearn.decomposition.PCA``: time and the variance
  the basis captures, relative to an exact SVD;
- exact search (``PatchIndex(method="exact")``) against scikit-learn's
  ``pairwise_distances_argmin_min`` (k = 1) and ``NearestNeighbors`` brute
  force (k = 3): time, the fraction of queries given their exact nearest
  neighbours and the largest error of the returned distances;
- Gaussian / Laplacian pyramids (``core.pyramid``) against scikit-image's
  ``pyramid_gaussian`` / ``pyramid_laplacian``: time, and whether the
  Laplacian pyramid reconstructs the image;
- histogram matching (``statistical.match_histogram``) against scikit-image's
  ``match_histograms``: time and the distance of the result's histogram to the
  reference's (1-Wasserstein);
- Ruiters' box downsampling and bilinear zoom against scikit-image's
  ``downscale_local_mean`` / ``block_reduce`` and ``resize``.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_packages.py [--quick] [--parts tsvq,pca,color,exact,skimage]
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from texsynth.core import pyramid
from texsynth.core.color import color_pca
from texsynth.core.search import PatchIndex, _kdtree, _tsvq
from texsynth.io import load_image
from texsynth.optimization._ruiters_neighborhoods import downsample as ruiters_downsample
from texsynth.statistical import match_histogram

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def patches(path, size, crop):
    img = load_image(TEXTURES / path)
    img = (img[..., None] if img.ndim == 2 else img)[..., :3]
    (r0, r1), (c0, c1) = crop
    view = sliding_window_view(img[r0:r1, c0:c1], (size, size), axis=(0, 1))
    return np.ascontiguousarray(view.reshape(-1, size * size * img.shape[-1]))


def best_of(fn, repeat=3):
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def exact_reference(vectors, queries, k=1):
    """Exact k nearest by direct differences in float64 (the ground truth)."""
    v = vectors.astype(np.float64)
    idx = np.empty((len(queries), k), np.int64)
    d2 = np.empty((len(queries), k))
    for s in range(0, len(queries), 256):
        q = queries[s:s + 256].astype(np.float64)
        d = ((q[:, None, :] - v[None]) ** 2).sum(-1) if v.shape[1] < 64 else (
            (q * q).sum(1)[:, None] - 2 * q @ v.T + (v * v).sum(1)[None])
        part = np.argsort(d, axis=1, kind="stable")[:, :k]
        idx[s:s + 256], d2[s:s + 256] = part, np.take_along_axis(d, part, 1)
    return idx, d2


def quality(vectors, queries, idx, truth_d2):
    """recall@1 (ties at equal distance count) and the mean ratio of returned to exact distance."""
    got = ((vectors[idx[:, 0]].astype(np.float64) - queries.astype(np.float64)) ** 2).sum(1)
    recall = float(np.mean(got <= truth_d2[:, 0] * (1 + 1e-9) + 1e-12))
    ok = truth_d2[:, 0] > 1e-12
    return recall, float(np.mean(got[ok] / truth_d2[ok, 0]))


def row(*cells):
    print("| " + " | ".join(str(c) for c in cells) + " |")


# --------------------------------------------------------------------------- TSVQ k-means
def sklearn_lloyd(kind):
    from sklearn.cluster import KMeans, MiniBatchKMeans

    def cluster(x, n_clusters, rng, n_iter=_tsvq._LLOYD_ITERATIONS):
        seed = int(rng.integers(2**31))
        if len(x) < n_clusters:
            return np.arange(len(x)), x.copy()
        if kind == "KMeans":
            km = KMeans(n_clusters, init="k-means++", n_init=1, max_iter=n_iter, tol=0.0, random_state=seed)
        else:
            km = MiniBatchKMeans(n_clusters, init="k-means++", n_init=1, max_iter=n_iter, batch_size=1024,
                                 random_state=seed)
        labels = km.fit_predict(x)
        return labels, km.cluster_centers_.astype(x.dtype)

    return cluster


def bench_tsvq(vectors, queries, truth_d2):
    print("\n### TSVQ k-means per tree node\n")
    row("k-means", "build s", "query s", "recall@1", "distance ratio")
    row(*["---"] * 5)
    original = _tsvq._lloyd
    for name, fn in (("texsynth Lloyd (k-means++, 5 iterations)", original),
                     ("sklearn KMeans (k-means++, n_init=1, max_iter=5)", sklearn_lloyd("KMeans")),
                     ("sklearn MiniBatchKMeans (batch 1024, max_iter=5)", sklearn_lloyd("MiniBatch"))):
        _tsvq._lloyd = fn
        try:
            build, index = best_of(lambda: PatchIndex(vectors, method="tsvq", rng=0), 2)
            query, (idx, _) = best_of(lambda: index.query(queries), 2)
        finally:
            _tsvq._lloyd = original
        recall, ratio = quality(vectors, queries, idx, truth_d2)
        row(name, f"{build:.2f}", f"{query:.2f}", f"{recall:.3f}", f"{ratio:.3f}")


# --------------------------------------------------------------------------- PCA
def bench_pca(samples):
    from sklearn.decomposition import PCA
    from sklearn.utils.extmath import randomized_svd

    print("\n### PCA of the kd-tree (24 components)\n")
    row("data", "routine", "s", "variance captured / exact")
    row(*["---"] * 4)
    for label, x in samples.items():
        centred = (x - x.mean(0)).astype(np.float32)
        exact_var = np.linalg.svd(centred.astype(np.float64), compute_uv=False)[:24] ** 2
        n = 24

        def captured(basis):  # (n, D) rows
            proj = centred.astype(np.float64) @ np.asarray(basis, np.float64).T
            return float((proj ** 2).sum() / exact_var.sum())

        t, (s, vt, _) = best_of(lambda: _kdtree.pca(centred, n, np.random.default_rng(0)))
        row(label, "texsynth (scatter matrix; randomized above 256-D, 1 power iteration)", f"{t:.3f}",
            f"{captured(vt[:n]):.4f}")
        t, (_, _, vt) = best_of(lambda: randomized_svd(centred, n, n_oversamples=10, n_iter=1, random_state=0))
        row(label, "sklearn randomized_svd (n_iter=1, 10 oversamples)", f"{t:.3f}", f"{captured(vt):.4f}")
        t, (_, _, vt) = best_of(lambda: randomized_svd(centred, n, random_state=0))
        row(label, "sklearn randomized_svd (defaults: n_iter=auto)", f"{t:.3f}", f"{captured(vt):.4f}")
        t, pca = best_of(lambda: PCA(n, svd_solver="full").fit(centred))
        row(label, "sklearn PCA(svd_solver='full')", f"{t:.3f}", f"{captured(pca.components_):.4f}")


# --------------------------------------------------------------------------- colour PCA
def bench_color_pca(images):
    from sklearn.decomposition import PCA

    print("\n### Colour PCA of an exemplar (3 x 3 covariance)\n")
    row("pixels", "routine", "s", "first axis vs texsynth's (|cos|)")
    row(*["---"] * 4)
    for label, image in images.items():
        pixels = np.ascontiguousarray(image.reshape(-1, image.shape[-1]), dtype=np.float64)
        t, (_, basis) = best_of(lambda: color_pca(pixels), 5)
        row(label, "texsynth color_pca (covariance, numpy eigh)", f"{t:.4f}", "1")
        for solver in ("covariance_eigh", "full"):
            try:
                t, pca = best_of(lambda: PCA(3, svd_solver=solver).fit(pixels), 5)
            except ValueError as exc:  # covariance_eigh needs scikit-learn >= 1.5
                row(label, f"sklearn PCA(svd_solver={solver!r})", "-", str(exc).splitlines()[0])
                continue
            row(label, f"sklearn PCA(svd_solver={solver!r})", f"{t:.4f}",
                f"{abs(float(pca.components_[0] @ basis[:, 0])):.6f}")


# --------------------------------------------------------------------------- exact search
def bench_exact(vectors, queries):
    from sklearn.metrics import pairwise_distances_argmin_min
    from sklearn.neighbors import NearestNeighbors

    print("\n### Exact search\n")
    row("routine", "k", "s", "exact neighbours", "within float32 rounding", "largest distance error")
    row(*["---"] * 6)
    for k in (1, 3):
        truth_i, truth_d2 = exact_reference(vectors, queries, k)

        def judge(idx, d2):
            got = ((vectors[idx].astype(np.float64) - queries[:, None].astype(np.float64)) ** 2).sum(-1)
            same = np.all(got <= truth_d2 * (1 + 1e-9) + 1e-12, axis=1)
            close = np.all(got <= truth_d2 * (1 + 1e-6) + 1e-9, axis=1)  # float32 eps is 1.2e-7
            return f"{np.mean(same):.4f}", f"{np.mean(close):.4f}", f"{np.max(np.abs(d2 - got)):.2e}"

        t, (idx, d2) = best_of(lambda: PatchIndex(vectors, method="exact").query(queries, k=k))
        row("texsynth PatchIndex exact", k, f"{t:.2f}", *judge(idx, d2))
        if k == 1:
            t, (i1, d1) = best_of(lambda: pairwise_distances_argmin_min(queries, vectors))
            row("sklearn pairwise_distances_argmin_min", k, f"{t:.2f}", *judge(i1[:, None], d1[:, None] ** 2))
        t, (dk, ik) = best_of(lambda: NearestNeighbors(n_neighbors=k, algorithm="brute").fit(vectors)
                              .kneighbors(queries))
        row("sklearn NearestNeighbors brute", k, f"{t:.2f}", *judge(ik, dk ** 2))


# --------------------------------------------------------------------------- skimage
def bench_skimage(image):
    from skimage.exposure import match_histograms
    from skimage.measure import block_reduce
    from skimage.transform import downscale_local_mean, pyramid_gaussian, pyramid_laplacian, resize

    print("\n### scikit-image\n")
    row("job", "routine", "s", "result")
    row(*["---"] * 4)
    levels = 5
    t, ours = best_of(lambda: pyramid.gaussian_pyramid(image, levels))
    row("Gaussian pyramid, 5 levels", "texsynth (binomial 5-tap REDUCE, Burt-Adelson)", f"{t:.3f}",
        "shapes " + " ".join(f"{p.shape[0]}" for p in ours))
    t, theirs = best_of(lambda: list(pyramid_gaussian(image, max_layer=levels - 1, channel_axis=-1)))
    row("", "skimage pyramid_gaussian (Gaussian sigma 2/3, then resize)", f"{t:.3f}",
        f"shapes {' '.join(str(p.shape[0]) for p in theirs)}; level 1 differs from REDUCE by up to "
        f"{np.abs(theirs[1] - ours[1]).max():.3f}")
    t, lap = best_of(lambda: pyramid.laplacian_pyramid(image, levels))
    back = pyramid.reconstruct_laplacian(lap)
    row("Laplacian pyramid", "texsynth (and reconstruct_laplacian)", f"{t:.3f}",
        f"reconstruction error {np.abs(back - image).max():.1e}")
    t, _ = best_of(lambda: list(pyramid_laplacian(image, max_layer=levels - 1, channel_axis=-1)))
    row("", "skimage pyramid_laplacian", f"{t:.3f}", "no reconstruction routine (its bands are G_i - blur(G_i))")

    rng = np.random.default_rng(0)
    noise = rng.random(image.shape[:2])
    reference = image[..., 0]
    targets = np.sort(reference.ravel())

    def w1(x):
        return float(np.mean(np.abs(np.sort(x.ravel()) - targets)))

    t, out = best_of(lambda: match_histogram(noise, reference))
    row("histogram matching (same size)", "texsynth match_histogram (sort, exact quantiles)", f"{t:.3f}",
        f"W1 to the reference {w1(out):.1e}")
    t, out = best_of(lambda: match_histograms(noise, reference))
    row("", "skimage match_histograms", f"{t:.3f}", f"W1 to the reference {w1(out):.1e}")

    r = 2
    image = image[: image.shape[0] // r * r, : image.shape[1] // r * r]  # skimage pads a remainder, Ruiters crops it
    h, w = image.shape[0] // r, image.shape[1] // r
    t, ours = best_of(lambda: image.reshape(h, r, w, r, -1).mean(axis=(1, 3)))
    row("box downsampling by 2", "reshape-mean (texsynth's until 0.2)", f"{t:.4f}", f"shape {ours.shape}")
    t, now = best_of(lambda: ruiters_downsample(image, r))
    row("", "texsynth now (Ruiters' _downsample: block_reduce)", f"{t:.4f}",
        f"max difference {np.abs(now - ours).max():.1e}")
    t, theirs = best_of(lambda: downscale_local_mean(image, (r, r, 1)))
    row("", "skimage downscale_local_mean", f"{t:.4f}", f"max difference {np.abs(theirs - ours).max():.1e}")
    t, theirs = best_of(lambda: block_reduce(image, (r, r, 1), np.mean))
    row("", "skimage block_reduce(np.mean)", f"{t:.4f}", f"max difference {np.abs(theirs - ours).max():.1e}")

    from scipy import ndimage

    small = image[::2, ::2]
    shape = image.shape
    t, ours = best_of(lambda: ndimage.zoom(small, (shape[0] / small.shape[0], shape[1] / small.shape[1], 1), order=1))
    row("bilinear 2x zoom", "scipy ndimage.zoom (used by Ruiters)", f"{t:.4f}", f"shape {ours.shape}")
    t, theirs = best_of(lambda: resize(small, shape, order=1, anti_aliasing=False))
    row("", "skimage resize(order=1)", f"{t:.4f}", f"max difference {np.abs(theirs - ours).max():.2f} (pixel-centre "
        "alignment differs)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sets")
    parser.add_argument("--parts", default="tsvq,pca,color,exact,skimage", help="comma-separated parts to run")
    args = parser.parse_args()
    parts = set(args.parts.split(","))
    s = 100 if args.quick else 230
    print(f"{platform.node()} {platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"numpy {np.__version__}")
    vectors = patches("embark/multiexample/1.jpg", 7, ((0, s), (0, s))).astype(np.float32)
    queries = patches("embark/multiexample/2.jpg", 7, ((100, 100 + s // 3), (100, 100 + s // 3))).astype(np.float32)
    print(f"colour 7x7 neighbourhoods (147-D): {len(vectors)} indexed, {len(queries)} queries")
    if "tsvq" in parts:
        _, truth_d2 = exact_reference(vectors, queries)
        bench_tsvq(vectors, queries, truth_d2)
    if "pca" in parts:
        large = patches("embark/1.jpg", 32, ((0, 64 if args.quick else 96), (0, 96))).astype(np.float32)
        bench_pca({"147-D colour 7x7 (20000 rows)": vectors[:20000], "3072-D colour 32x32 (1365 rows)": large[:1365]})
    image = load_image(TEXTURES / "embark/multiexample/1.jpg")[..., :3]
    if "color" in parts:
        bench_color_pca({f"{n}x{n} photograph": image[:n, :n] for n in (256, min(image.shape[:2]))})
    if "exact" in parts:
        bench_exact(vectors, queries)
    image = image if not args.quick else image[:256, :256]
    if "skimage" in parts:
        bench_skimage(np.ascontiguousarray(image))


if __name__ == "__main__":
    main()
