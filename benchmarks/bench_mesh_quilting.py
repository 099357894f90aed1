"""Mesh quilting: about 200 elements over a 20,000-face surface in at most 2 minutes.

Run: python benchmarks/bench_mesh_quilting.py [--seeds 1] [--swatches rivets,pebbles,spikes] [--elements 250]

The surface is ``texsynth.surface.bumpy(10242, rng=0)`` (20,480 faces, bumps of 15 % of the radius); the swatch
``texsynth.data.swatch(name)`` (16 x 16 units, 80-106 elements), scaled so that its element density would put
``--elements`` (250) elements on the surface: about 200 are placed. Side by side in the same run, the
references: the same quilting with random swatch offsets (``placement="random"``), and the random placement of
as many elements at uniformly random points of the surface. Printed per run: wall time, elements and faces
placed, the mean element-set distance ``E(o)`` of the chosen offsets, the nearest-neighbour distances of the
element centres (in swatch units) against the swatch's own: their 1-Wasserstein distance and the share of
centres nearer than the swatch's closest pair, the elements placed against those the swatch's density would put
there, and the shell: the largest distance of an output vertex from the surface (sampled densely), against the
thickness.
"""

import argparse
import time

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree
from scipy.stats import wasserstein_distance

from texsynth import surface
from texsynth.data import swatch
from texsynth.geometry import mesh_quilting

TARGET = 120.0  # seconds for 200 elements over 20,000 faces
SIDE = 16.0


def centres_of(vertices, faces):
    """Centres of the swatch's elements (their boxes' centres in the plane), as the method takes them."""
    e = np.r_[faces[:, [0, 1]], faces[:, [1, 2]]]
    labels = connected_components(coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(len(vertices),) * 2),
                                  directed=False)[1]
    order = np.argsort(labels)
    groups = np.split(vertices[order, :2], np.flatnonzero(np.diff(labels[order])) + 1)
    return np.array([0.5 * (g.min(0) + g.max(0)) for g in groups])


def surface_samples(vertices, faces, per_face=12, rng=0):
    gen = np.random.default_rng(rng)
    s, t = np.sqrt(gen.random((len(faces), per_face))), gen.random((len(faces), per_face))
    a, b, c = (vertices[faces[:, i]][:, None] for i in range(3))
    return ((1 - s)[..., None] * a + (s * (1 - t))[..., None] * b + (s * t)[..., None] * c).reshape(-1, 3)


def spacing(points, unit_length, reference, closest):
    d = cKDTree(points).query(points, k=2)[0][:, 1] / unit_length
    return wasserstein_distance(d, reference), float(np.mean(d < closest))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--swatches", default="rivets,pebbles,spikes")
    parser.add_argument("--elements", type=int, default=250, help="elements at the swatch's density (about 4/5 "
                        "of them are placed: the seams are sparser)")
    args = parser.parse_args()
    base = surface.bumpy(10242, rng=0)
    v, f = base.vertices, base.faces
    a, b, c = (v[f[:, i]] for i in range(3))
    areas = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    samples = cKDTree(surface_samples(v, f))
    print(f"surface: bumpy sphere, {len(v)} vertices, {len(f)} faces, area {areas.sum():.2f}")
    mesh_quilting(swatch("rivets", 8.0), surface.sphere(162), unit_length=0.3, rng=0)  # warm-up
    rows = []
    for name in args.swatches.split(","):
        sw = swatch(name)
        centres = centres_of(*sw)
        interior = np.all((centres > 2.0) & (centres < SIDE - 2.0), axis=1)
        reference = cKDTree(centres).query(centres[interior], k=2)[0][:, 1]
        closest = float(cKDTree(centres).query(centres, k=2)[0][:, 1].min())
        unit_length = float(np.sqrt(len(centres) * areas.sum() / (args.elements * SIDE ** 2)))
        print(f"\nswatch {name}: {len(centres)} elements, {len(sw[1])} faces; unit_length {unit_length:.4f}, "
              f"median spacing {np.median(reference):.2f}, closest pair {closest:.2f} swatch units")
        expected = len(centres) / SIDE ** 2 * areas.sum() / unit_length ** 2  # elements at the swatch's density
        print(f"{'arrangement':<16}{'seed':>5}{'seconds':>9}{'elements':>9}{'density':>8}{'faces':>8}{'E(o)':>7}"
              f"{'W1 nn':>7}{'too close':>10}{'shell max/thickness':>21}")
        for seed in range(args.seeds):
            for placement in ("matched", "random"):
                t = time.perf_counter()
                out_v, out_f, info = mesh_quilting(sw, base, unit_length=unit_length, placement=placement, rng=seed,
                                                   return_info=True)
                seconds = time.perf_counter() - t
                w1, close = spacing(info.element_centers, unit_length, reference, closest)
                shell = float(samples.query(out_v)[0].max())
                cost = float(info.costs[info.costs > 0].mean())
                print(f"{placement:<16}{seed:>5}{seconds:>9.1f}{len(info.element_sources):>9}"
                      f"{len(info.element_sources) / expected:>8.2f}{len(out_f):>8}"
                      f"{cost:>7.2f}{w1:>7.3f}{close:>10.3f}{shell / info.thickness:>21.3f}")
                rows.append((name, placement, seconds, len(info.element_sources), w1))
            gen = np.random.default_rng(seed)
            n = len(info.element_sources)
            pick = gen.choice(len(f), size=n, p=areas / areas.sum())
            s, t = np.sqrt(gen.random(n)), gen.random(n)
            points = (1 - s)[:, None] * a[pick] + (s * (1 - t))[:, None] * b[pick] + (s * t)[:, None] * c[pick]
            w1, close = spacing(points, unit_length, reference, closest)
            print(f"{'random points':<16}{seed:>5}{'-':>9}{n:>9}{n / expected:>8.2f}{'-':>8}{'-':>7}{w1:>7.3f}"
                  f"{close:>10.3f}{'-':>21}")
    worst = max(r[2] for r in rows if r[1] == "matched")
    print(f"\nslowest matched run {worst:.1f} s against the target {TARGET:.0f} s: "
          f"{'met' if worst <= TARGET else 'NOT met'}")
    placed = [r[3] for r in rows if r[1] == "matched"]
    print(f"docs/benchmarks.md: mesh quilting, {min(placed)}-{max(placed)} elements on a 20,480-face bumpy sphere: "
          f"{min(r[2] for r in rows if r[1] == 'matched'):.1f}-{worst:.1f} s (target {TARGET:.0f} s)")


if __name__ == "__main__":
    main()
