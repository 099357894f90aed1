"""Steerable pyramid: build + reconstruct, texsynth vs pyrtools' SteerablePyramidFreq.

Run: python benchmarks/bench_pyramid.py [--size 512] [--repeat 5]

Both decompose the same real texture (lcv/metal.pgm, tiled/cropped to the size) with 4 scales
and 4 orientations and reconstruct it; the table gives the best time of ``--repeat`` runs and the
maximum absolute reconstruction error. texsynth's time includes building the masks (a new
SteerablePyramid per run), as pyrtools builds its masks in every constructor call. A second row
reuses the pyramid object (masks precomputed), which is how Heeger-Bergen and
Portilla-Simoncelli use it.
"""

import argparse
import time
from pathlib import Path

import numpy as np

from texsynth.io import load_image
from texsynth.core.pyramid import SteerablePyramid, laplacian_pyramid, reconstruct_laplacian

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def best_time(fn, repeat):
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    n = args.size
    metal = load_image(TEXTURES / "lcv" / "metal.pgm")
    reps = (n // metal.shape[0] + 1, n // metal.shape[1] + 1)
    image = np.tile(metal, reps)[:n, :n]
    rows = []

    def ours_fresh():
        pyr = SteerablePyramid(image.shape, 4, 4)
        return pyr.reconstruct(pyr.decompose(image))

    t, rec = best_time(ours_fresh, args.repeat)
    rows.append(("texsynth SteerablePyramid (masks built each run)", t, np.abs(rec - image).max()))
    pyr = SteerablePyramid(image.shape, 4, 4)
    t, rec = best_time(lambda: pyr.reconstruct(pyr.decompose(image)), args.repeat)
    rows.append(("texsynth SteerablePyramid (masks reused)", t, np.abs(rec - image).max()))
    cpyr = SteerablePyramid(image.shape, 4, 4, is_complex=True)
    t, rec = best_time(lambda: cpyr.reconstruct(cpyr.decompose(image)), args.repeat)
    rows.append(("texsynth SteerablePyramid complex (masks reused)", t, np.abs(rec - image).max()))
    try:
        import pyrtools as pt
    except ImportError:
        rows.append(("pyrtools SteerablePyramidFreq: NOT INSTALLED (pip install pyrtools)", np.nan, np.nan))
    else:
        def theirs():
            p = pt.pyramids.SteerablePyramidFreq(image, height=4, order=3)
            return p.recon_pyr()

        t, rec = best_time(theirs, args.repeat)
        rows.append((f"pyrtools {pt.__version__} SteerablePyramidFreq", t, np.abs(rec - image).max()))

        def theirs_complex():
            p = pt.pyramids.SteerablePyramidFreq(image, height=4, order=3, is_complex=True)
            return p.recon_pyr()

        t, rec = best_time(theirs_complex, args.repeat)
        rows.append((f"pyrtools {pt.__version__} SteerablePyramidFreq complex", t, np.abs(rec - image).max()))
        ref = pt.pyramids.SteerablePyramidFreq(image, height=4, order=3).pyr_coeffs
        ours = pyr.decompose(image)
        agreement = max(np.abs(ref[(s, k)] / 2**s - ours.bands[s][k]).max() / np.abs(ours.bands[s][k]).max()
                        for s in range(4) for k in range(4))
        lap = pt.pyramids.LaplacianPyramid
        t, rec = best_time(lambda: lap(image, height=5).recon_pyr(), args.repeat)
        rows.append((f"pyrtools {pt.__version__} LaplacianPyramid (5 levels)", t, np.abs(rec - image).max()))
    t, rec = best_time(lambda: reconstruct_laplacian(laplacian_pyramid(image, 5)), args.repeat)
    rows.append(("texsynth laplacian_pyramid (5 levels)", t, np.abs(rec - image).max()))

    print(f"steerable pyramid, {n}x{n} float64, 4 scales x 4 orientations, build + reconstruct "
          f"(best of {args.repeat})")
    print(f"{'implementation':<62} {'time [ms]':>10} {'max |error|':>12}")
    for name, t, err in rows:
        print(f"{name:<62} {t * 1e3:10.1f} {err:12.2e}")
    if "agreement" in locals():
        print(f"oriented bands: max |pyrtools / 2^s - texsynth| / max|texsynth| = {agreement:.1e} "
              "(pyrtools' lookup-table masks)")


if __name__ == "__main__":
    main()
