"""Harrison patchwork: speed (O(n) in output pixels) and the weight the neighbour bound omits.

Run: python benchmarks/bench_patchwork.py [--repeat 3]   (from the repository root, with texsynth installed)

Targets (issue 4): 1024x1024 colour output in at most 0.5 s; times for 256^2 .. 2048^2 that grow
linearly; a 128x128x64-frame video in at most 10 s; transfer onto a 512x512 pattern in at most 10 s.

Side by side, in the same run:
- ``copy``: the cost of merely blending two images of the output size (``0.5*a + 0.5*b``), the
  floor any per-pixel method pays;
- ``all cells``: a plain numpy implementation of eq. 2 that sums over every cell for every pixel
  (no neighbour bound), float32, chunked - O(pixels x cells), i.e. quadratic in the output side
  at a fixed grid spacing. Run on the small sizes only.

Then the weight the m x m neighbour bound omits, measured against the all-cells sum, as the share
of sum_i w_i(x)^2 (the denominator of eq. 2) over pixels: mean and maximum, for f = 2, 6, 20;
once for the plain truncation (the cells outside the block dropped) and once with the smooth
taper the module applies (w_i phi_i, phi_i falling to 0 over the outer half grid spacing of each
cell's reach), which removes a little more weight in exchange for a weight field without steps.
Exemplar: embark/2.jpg (ink, 400x400 colour); grid 64, f = 6 unless stated.
"""

import argparse
import time
from pathlib import Path

import numpy as np

from texsynth.patch import _patchwork as pw
from texsynth.patch import patchwork_transfer, patchwork_video
from texsynth.io import load_image

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def all_cells(exemplar, info, shape, f=6.0):
    """Reference: eq. 2 summed over every cell (float32, rows in chunks)."""
    H, W = shape
    ex = exemplar.astype(np.float32)
    a = ex.reshape(-1, 3).mean(0)
    out = np.empty((H, W, 3), np.float32)
    cols = np.arange(W, dtype=np.float32)
    for r0 in range(0, H, 32):
        r = np.arange(r0, min(H, r0 + 32), dtype=np.float32)[:, None]
        num = np.zeros((len(r), W, 3), np.float32)
        den = np.zeros((len(r), W), np.float32)
        d2min = np.full((len(r), W), np.inf, np.float32)
        for py, px in info.p:
            d2min = np.minimum(d2min, (r - py) ** 2 + (cols - px) ** 2)
        for (py, px), (qy, qx) in zip(info.p, info.q):
            w = (d2min / ((r - py) ** 2 + (cols - px) ** 2)) ** (f / 2)
            sy = np.clip((r - py + qy).astype(int), 0, ex.shape[0] - 1)
            sx = np.clip((cols - px + qx).astype(int), 0, ex.shape[1] - 1)
            num += (ex[sy, sx] - a) * w[..., None]
            den += w * w
        out[r0 : r0 + len(r)] = num / np.sqrt(den)[..., None] + a
    return out


def omitted_share(size, spacing, f, m, seed=0, taper=True):
    """Share of sum_i w_i^2 that the m x m bound leaves out (tapered or plainly cut): (mean, max) over pixels."""
    geom = pw.Geometry((size, size), (size, size), spacing, f, m, False, np.random.default_rng(seed),
                        choose_q=False)
    H = W = size
    included = np.zeros((H, W))
    for band in geom.bands():
        parts, _ = geom.band_weights(band, taper=taper)
        total = sum(w.astype(np.float64) ** 2 for _, w, *_ in parts)
        idx, rows = geom.to_output(band, total[..., None])
        included[idx] = rows[..., 0]
    r, c = np.mgrid[:H, :W]
    p = np.stack([geom.py.ravel(), geom.px.ravel()], 1)
    d2 = np.stack([(r - py) ** 2 + (c - px) ** 2 for py, px in p], 0)
    everything = ((d2.min(0) / d2) ** f).sum(0)  # the same relative weights, every cell
    share = 1 - included / everything
    return share.mean(), share.max()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    ink = load_image(TEXTURES / "embark" / "2.jpg").astype(np.float32)

    print("Image synthesis, colour, float32 exemplar 400x400, grid 64, f = 6, neighbors = 4")
    print(f"{'output':>10} {'patchwork s':>12} {'ns/pixel':>9} {'copy s':>8} {'all cells s':>12} {'cells':>6}")
    for n in (256, 512, 1024, 2048):
        pw.patchwork(ink, n, rng=0)  # warm-up
        t = best_of(lambda: pw.patchwork(ink, n, rng=0), args.repeat)
        a, b = np.zeros((n, n, 3), np.float32), np.ones((n, n, 3), np.float32)
        t_copy = best_of(lambda: 0.5 * a + 0.5 * b, args.repeat)
        _, info = pw.patchwork(ink, n, rng=0, return_info=True)
        ref = ""
        if n <= 512:
            t_ref = best_of(lambda: all_cells(ink, info, (n, n)), 1)
            ref = f"{t_ref:12.3f}"
            out = pw.patchwork(ink, n, rng=0)
            err = np.abs(np.clip(all_cells(ink, info, (n, n)), 0, 1) - out).mean()
            ref += f"  (mean |diff| {err:.1e})"
        print(f"{n:>5}x{n:<4} {t:12.3f} {1e9 * t / n / n:9.1f} {t_copy:8.3f} {ref:>12} {len(info.p):>6}")

    print("\nShare of sum w_i^2 omitted by the m x m neighbour bound (256x256, grid 32, 64 cells)")
    print(f"{'f':>4} {'m':>3} {'cut: mean':>10} {'max':>10} {'tapered: mean':>14} {'max':>10}")
    for f in (2, 6, 20):
        for m in (3, 4, 5):
            cut = omitted_share(256, 32, float(f), m, taper=False)
            tapered = omitted_share(256, 32, float(f), m)
            print(f"{f:>4} {m:>3} {cut[0]:10.2e} {cut[1]:10.2e} {tapered[0]:14.2e} {tapered[1]:10.2e}")

    print("\nVideo: 32-frame 160x160 colour input (a window sliding over embark/1.jpg), grid 64, f = 6")
    water = load_image(TEXTURES / "embark" / "1.jpg").astype(np.float32)
    clip = np.stack([water[t : t + 160, 2 * t : 2 * t + 160] for t in range(32)])
    t = best_of(lambda: patchwork_video(clip, 128, 64, rng=0), args.repeat)
    t_copy = best_of(lambda: np.repeat(clip[:1], 64, 0)[:, :128, :128] * np.float32(1.0), args.repeat)
    print(f"  128x128x64 output: {t:.3f} s   (copy of the same amount of frames: {t_copy:.3f} s)")

    print("\nTransfer: ink texture (400x400) onto skimage camera resized to 512x512, grid 16, f = 2, 64 candidates")
    from skimage import data as skdata
    from skimage.transform import resize

    pattern = np.repeat(resize(skdata.camera(), (512, 512)).astype(np.float32)[..., None], 3, -1)
    t = best_of(lambda: patchwork_transfer(ink, pattern, rng=0), args.repeat)
    t_syn = best_of(lambda: pw.patchwork(ink, 512, grid_spacing=16, sharpness=2, rng=0), args.repeat)
    print(f"  512x512 pattern: {t:.3f} s   (the same synthesis without matching: {t_syn:.3f} s)")


if __name__ == "__main__":
    main()
