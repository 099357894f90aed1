"""BTF synthesis (Tong et al. 2002): textons, a 50,000-vertex surface texton map, rendering, and quality.

Run: python benchmarks/bench_btf.py [--seeds 3] [--no-reference]

Targets (issue 36): the 3-D textons of a 64-image 128 x 128 BTF in at most 30 s; a 50,000-vertex surface
texton map in at most 2 minutes; rendering one light/view in under 1 s. The sample is
``texsynth.data.btf("stones", 128, n_lights=64)``. Side by side in the same run, the references:

- textons: k-means (scikit-learn ``MiniBatchKMeans``, the same 64 clusters) on the full 3072-D responses
  instead of their 48 leading principal axes, with the k-means energy of both in the full space;
- surface: ``synthesize_surface`` on a 128 x 128 colour photograph (``brick``) with the same options, i.e. the
  vertex synthesis without textons;
- rendering: ``render_mesh`` of the rendered surface (one 512 x 512 view).

Quality (``--seeds``; the setting of tests/test_btf.py: a 64 x 64, 24-light sample, 32 textons): the texture
energy (texsynth.metrics) of two opposite lights stacked as one 2-channel image: (a) two measured lights,
planar 48 x 48 and on a flat square; (b) two new lights between the measured ones (azimuths 11.25 and
191.25 degrees, elevation 37.5), planar, each rendered from its 3 nearest images; against images synthesised
each on its own, the same way (lower is better; the ratio is baseline / ours).
"""

import argparse
import os
import resource
import sys
import time

import numpy as np

import texsynth
from texsynth.core.btf import btf_textons, filter_responses, leung_malik_filters
from texsynth.data import btf
from texsynth.surface import render_btf_surface, synthesize_btf_surface

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))

TEXTON_TARGET, SURFACE_TARGET, RENDER_TARGET = 30.0, 120.0, 1.0


def peak_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def full_energy(responses, labels):
    """k-means energy in the full response space: sum of squared distances to each cluster's mean."""
    total = 0.0
    for t in np.unique(labels):
        members = responses[labels == t]
        total += float(((members - members.mean(0)) ** 2).sum())
    return total


def textons_part(sample, reference):
    t = time.perf_counter()
    textons = btf_textons(sample, 64, rng=0)
    seconds = time.perf_counter() - t
    stages = ", ".join(f"{k} {v:.1f}" for k, v in textons.stage_seconds.items())
    verdict = "target met" if seconds <= TEXTON_TARGET else "target MISSED"
    responses = filter_responses(sample.images, leung_malik_filters()).reshape(-1, 48 * len(sample))
    print(f"textons  ours: {seconds:6.1f} s ({stages}); full-space k-means energy "
          f"{full_energy(responses, textons.labels.ravel()):.0f}  {verdict} (<= {TEXTON_TARGET:.0f} s)")
    if reference:
        from sklearn.cluster import MiniBatchKMeans

        t = time.perf_counter()
        labels = MiniBatchKMeans(64, batch_size=4096, n_init=1, random_state=0).fit(responses).labels_
        print(f"textons  reference (MiniBatchKMeans on all {responses.shape[1]} dimensions): "
              f"{time.perf_counter() - t:6.1f} s; energy {full_energy(responses, labels):.0f}")
    print(f"    peak RSS so far {peak_mib():.0f} MiB (responses {responses.nbytes / 2**20:.0f} MiB)")
    return textons


def surface_part(sample, textons, reference):
    ball = texsynth.surface.sphere()
    t = time.perf_counter()
    surface, info = synthesize_btf_surface(ball, sample, n_vertices=50_000, textons=textons, rng=0, return_info=True)
    seconds = time.perf_counter() - t
    stages = ", ".join(f"{k} {v:.1f}" for k, v in info.synthesis.stage_seconds.items())
    verdict = "target met" if seconds <= SURFACE_TARGET else "target MISSED"
    print(f"surface  ours: {len(surface.sources)} vertices in {seconds:6.1f} s ({stages}); texton share "
          f"{info.texton_share:.2f}  {verdict} (<= {SURFACE_TARGET:.0f} s); peak RSS {peak_mib():.0f} MiB")
    if reference:
        t = time.perf_counter()
        texsynth.synthesize_surface(ball, texsynth.data.load("brick")[:128, :128], n_vertices=50_000, rng=0)
        print(f"surface  reference (synthesize_surface, brick 128x128 colour): {time.perf_counter() - t:6.1f} s")
    t = time.perf_counter()
    lit = render_btf_surface(surface, (-0.5, 0.6, 0.8))
    seconds = time.perf_counter() - t
    verdict = "target met" if seconds <= RENDER_TARGET else "target MISSED"
    t = time.perf_counter()
    texsynth.render_mesh(lit, 512, views=1, ambient=1.0)
    print(f"render   ours: one light in {seconds:.3f} s  {verdict} (< {RENDER_TARGET:.0f} s); reference "
          f"render_mesh 512x512, one view: {time.perf_counter() - t:.3f} s")


def quality_part(seeds):
    from test_btf import (COHERENT, NEIGHBORHOOD, NEW_LIGHTS, SIDE, blend_nearest, flat_square, raster)
    from texsynth.core.btf import render_btf
    from texsynth.metrics import texture_energy
    from texsynth.pixel import synthesize_btf

    sample = btf("stones", SIDE, n_lights=24)
    textons = btf_textons(sample, 32, rng=0)
    pair = lambda a, b: np.stack([a, b], axis=-1)  # noqa: E731
    reference = pair(sample.images[0], sample.images[4])
    near = [np.argsort(((sample.lights - light) ** 2).sum(1))[:3] for light in NEW_LIGHTS]
    between = pair(*[render_btf(sample, light) for light in NEW_LIGHTS])
    square = flat_square()
    along_x = np.tile([1.0, 0.0, 0.0], (len(square.vertices), 1))
    schedule = texsynth.SurfaceSchedule(levels=2)
    rows = []
    for seed in range(seeds):
        out = synthesize_btf(sample, 48, textons=textons, neighborhood=NEIGHBORHOOD, rng=seed)
        alone = {i: texsynth.synthesize_pixels(sample.images[i], 48, neighborhood=NEIGHBORHOOD, search=COHERENT,
                                               rng=seed + 10 * i) for i in {0, 4, *near[0], *near[1]}}
        planar = (texture_energy(pair(out.images[0], out.images[4]), reference),
                  texture_energy(pair(alone[0], alone[4]), reference))
        new = (texture_energy(pair(*[render_btf(out, light) for light in NEW_LIGHTS]), between),
               texture_energy(pair(*[blend_nearest([alone[i] for i in n], sample.lights[n], light)
                                     for n, light in zip(near, NEW_LIGHTS)]), between))
        surface = synthesize_btf_surface(square, sample, pixel_size=1 / 56, field=along_x, textons=textons,
                                         schedule=schedule, rng=seed)
        ours = pair(*[raster(surface.mesh, render_btf_surface(surface, sample.lights[i]).colors[:, 0])
                      for i in (0, 4)])
        separate = []
        for i in (0, 4):
            _, info = texsynth.synthesize_surface(square, sample.images[i], pixel_size=1 / 56, field=along_x,
                                                  schedule=schedule, rng=seed + 10 * i, return_info=True)
            separate.append(raster(info.levels[0], sample.images[i][info.sources[:, 0], info.sources[:, 1]]))
        flat = (texture_energy(ours, reference), texture_energy(pair(*separate), reference))
        rows.append((planar, new, flat))
        names = ("planar pair", "planar new lights", "flat square pair")
        print(f"quality seed {seed}: " + "; ".join(f"{name} ours {a:.4f} alone {b:.4f} ratio {b / a:.1f}"
                                                   for name, (a, b) in zip(names, (planar, new, flat))), flush=True)
    for k, name in enumerate(("planar pair", "planar new lights", "flat square pair")):
        ratios = [r[k][1] / r[k][0] for r in rows]
        print(f"quality {name}: ratio (baseline / ours) {min(ratios):.1f}-{max(ratios):.1f} over seeds 0-{seeds - 1}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--no-reference", action="store_true")
    args = parser.parse_args()
    texsynth.synthesize_surface(texsynth.surface.sphere(2), texsynth.data.load("bread")[:32, :32], n_vertices=300,
                                schedule=texsynth.SurfaceSchedule(levels=1), rng=0)  # warm-up: imports
    t = time.perf_counter()
    sample = btf("stones", 128, n_lights=64)
    print(f"sample: {len(sample)} images of 128x128 made in {time.perf_counter() - t:.1f} s")
    textons = textons_part(sample, not args.no_reference)
    surface_part(sample, textons, not args.no_reference)
    if args.seeds:
        quality_part(args.seeds)


if __name__ == "__main__":
    main()
