"""Source-coordinate maps: ``apply_coordinates`` of a 2048 x 2048 map to four channels, against plain indexing.

Run: nice -n 10 python benchmarks/bench_coordinates.py [--repeat 3]   (from the repository root)

Target (issue 19): a 2048^2 map applied to 4 channels in at most 1 s. The channels are a PBR set made from a
512^2 crop of a photograph: albedo (RGB float64), a normal map (RGB uint16, ``normals=True``), a height
(grey float32) and a roughness (grey uint8). Two maps: image quilting's copy map ``(H, W, 2)`` and
patch-based sampling's feathered blend ``(H, W, K, 2)`` with weights (K = 4). Beside them in the same run:
plain numpy fancy indexing ``channel[rows, cols]`` of the four channels (the floor of a copy), and
``scipy.ndimage.map_coordinates`` (order 0, nearest: a copy) of the same channels, one channel plane at a time.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

# benchmarks/ is on the path when a script runs
from bench_seam_carving import best_of

ROOT = Path(__file__).resolve().parents[1]
PHOTOS = ROOT / "benchmarks" / "photos"


def pbr_set(albedo):
    """Albedo, normal (uint16), height (float32) and roughness (uint8) of one material, from its photograph."""
    lum = albedo @ np.array([0.2125, 0.7154, 0.0721])
    height = ndimage.gaussian_filter(lum, 2.0)
    gy, gx = np.gradient(height)
    normal = np.stack([-8 * gx, 8 * gy, np.ones_like(gx)], -1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    normal16 = np.rint((normal + 1) / 2 * 65535).astype(np.uint16)
    rough = np.rint((1 - ndimage.gaussian_gradient_magnitude(lum, 1.0).clip(0, 0.25) * 4) * 255).astype(np.uint8)
    return [albedo, normal16, height.astype(np.float32), rough]


def fancy(channels, coords):
    rows, cols = coords[..., 0], coords[..., 1]
    return [c[rows, cols] for c in channels]


def scipy_nearest(channels, coords):
    at = [coords[..., 0], coords[..., 1]]
    out = []
    for c in channels:
        planes = [c] if c.ndim == 2 else [c[..., k] for k in range(c.shape[2])]
        rendered = [ndimage.map_coordinates(p, at, order=0) for p in planes]
        out.append(rendered[0] if c.ndim == 2 else np.stack(rendered, -1))
    return out


def main(repeat, size):
    from texsynth import apply_coordinates, patch_sampling, quilt
    from texsynth.io import load_image

    albedo = np.ascontiguousarray(load_image(PHOTOS / "cobblestones_1.png")[:512, :512, :3])
    channels = pbr_set(albedo)
    started = time.perf_counter()
    copy, copy_info = quilt(albedo[:256, :256], size, rng=0, return_info=True)
    t_quilt = time.perf_counter() - started
    started = time.perf_counter()
    blend, blend_info = patch_sampling(albedo[:256, :256], size, rng=0, return_info=True)
    t_sampling = time.perf_counter() - started
    # the maps point into a 256^2 crop; channels of 512^2 are rendered through them (the crop is their top-left)
    normals = [False, True, False, False]
    print(f"apply_coordinates: {size}^2 maps, 4 channels of 512^2 (albedo RGB float64, normal RGB uint16, "
          f"height float32, roughness uint8), best of {repeat}; load {os.getloadavg()[0]:.1f}")
    print(f"(making the maps: quilt {t_quilt:.1f} s, patch sampling {t_sampling:.1f} s, K = "
          f"{blend_info.coordinates.shape[2]})")
    print(f"{'what':<58} {'seconds':>8}")
    rows = [
        ("apply_coordinates, copy map (quilt), 4 channels",
         lambda: apply_coordinates(channels, copy_info, normals=normals)),
        ("apply_coordinates, blend map (patch sampling, K=4), 4 channels",
         lambda: apply_coordinates(channels, blend_info, normals=normals)),
        ("  reference: fancy indexing channel[rows, cols], 4 channels", lambda: fancy(channels, copy_info.coordinates)),
        ("  reference: fancy indexing, albedo only", lambda: fancy(channels[:1], copy_info.coordinates)),
        ("  reference: scipy.ndimage.map_coordinates order 0, 4 channels",
         lambda: scipy_nearest(channels, copy_info.coordinates)),
    ]
    results = {}
    for label, call in rows:
        seconds, value = best_of(call, repeat)
        results[label] = value
        print(f"{label:<58} {seconds:8.3f}")
    same = all(np.array_equal(a, b) for a, b in zip(results[rows[2][0]], results[rows[4][0]]))
    copied = results[rows[0][0]]
    exact = all(np.array_equal(a, b) for a, b in zip([copied[0], copied[2], copied[3]],
                                                       [results[rows[2][0]][k] for k in (0, 2, 3)]))
    print(f"copy map: apply_coordinates equals fancy indexing: {exact}; fancy indexing equals scipy: {same}")
    print("target: a 2048^2 map to 4 channels <= 1 s")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--size", type=int, default=2048)
    args = parser.parse_args()
    main(args.repeat, args.size)
