"""Image quilting and the seams it stands on: speed, side by side, and the docs' figures.

Run: nice -n 10 python benchmarks/bench_quilting.py [--repeat 2] [--figures]   (from the repository root)

Targets (issue 17): quilting 256x256 -> 1024x1024 colour in at most 3 s; patch-based sampling the same
(``benchmarks/bench_patch_sampling.py`` measures it, with the same table).

Side by side, in the same run:
- patch-based sampling and ``patchwork`` (Harrison's patchwork, texsynth.patchwork, grid 64) on the same inputs,
  the library's other fast patch methods;
- the minimum-error boundary cut (texsynth.core.seams) against scikit-image's MCP restricted to the three moves
  downwards (the same path) and ``route_through_array`` (its default 8 moves: not a seam, for scale), on quilting's
  overlap strips and on a 512 x 512 energy map (seam carving's size);
- graph_cut on square overlaps of 64, 128 and 256 pixels.

``--figures`` writes the docs' figures to docs/_static/ (textures that may be copied: skimage, lcv, jcjohnson,
embark) and, for looking, 1024 x 1024 outputs from 256 px textures to benchmarks/output/ (quilting's and patch-based
sampling's: the two share their block grid).
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TEXTURES = ROOT.parent / "shared" / "textures"
PHOTOS = ROOT / "benchmarks" / "photos"


def best_of(fn, repeat, *args, **kwargs):
    """The shortest wall time of ``repeat`` calls of ``fn(*args, **kwargs)``, and its result."""
    times, result = [], None
    for _ in range(repeat):
        started = time.perf_counter()
        result = fn(*args, **kwargs)
        times.append(time.perf_counter() - started)
    return min(times), result


def load(path, size=None):
    from texsynth.io import load_image

    image = load_image(path)
    if image.ndim == 3 and image.shape[2] == 4:
        image = image[..., :3]
    return np.ascontiguousarray(image if size is None else image[:size, :size])


def load_scaled(path, size):
    """A photograph scaled (area-averaged) to ``size`` pixels: the whole photo at a texture's scale."""
    from skimage.transform import resize

    image = load(path)
    return resize(image, (size, size) + image.shape[2:], anti_aliasing=True)


def speed(repeat):
    import texsynth
    from texsynth.patch._patch_sampling import patch_sampling
    from texsynth.patch._quilting import quilt

    print(f"Synthesis 256x256 -> 1024x1024 colour (benchmarks/photos, top-left 256 px crops), best of {repeat}; "
          f"load {os.getloadavg()[0]:.1f}")
    print(f"{'photo':<16} {'quilt s':>8} {'patch sampling s':>17} {'patchwork s':>12}")
    for name in ("bricks_1", "pebbles_1", "cobblestones_1", "moss_1"):
        ex = load(PHOTOS / f"{name}.png", 256)
        t_q, _ = best_of(quilt, repeat, ex, 1024, rng=0)
        t_p, _ = best_of(patch_sampling, repeat, ex, 1024, rng=0)
        t_h, _ = best_of(texsynth.patchwork, repeat, ex, 1024, grid_spacing=64, rng=0)
        print(f"{name:<16} {t_q:8.2f} {t_p:17.2f} {t_h:12.2f}")
    ex = load(PHOTOS / "bricks_1.png", 256)
    _, (_, info) = best_of(lambda: quilt(ex, 1024, rng=0, return_info=True), 1)
    print(f"  quilt's stages (bricks_1): {len(info.sources)} blocks of {info.block} px, overlap {info.overlap}: "
          f"search {info.stage_seconds['search']:.2f} s, cuts and pasting {info.stage_seconds['paste']:.2f} s")


def seams(repeat):
    from skimage.graph import MCP, route_through_array

    from texsynth.core.seams import cumulative_cost, graph_cut, minimum_error_boundary

    rng = np.random.default_rng(0)
    strips = [rng.random((64, 11)) for _ in range(800)]  # the strips of a 1024^2 quilt (400 blocks, 2 each)
    energy = rng.random((512, 512))
    down = [(1, -1), (1, 0), (1, 1)]

    def mcp_seam(cost):
        mcp = MCP(cost, offsets=down, fully_connected=True)
        cumulative, _ = mcp.find_costs(starts=[(0, j) for j in range(cost.shape[1])])
        return mcp.traceback((cost.shape[0] - 1, int(np.argmin(cumulative[-1]))))

    def route(cost):
        return route_through_array(cost, (0, 0), (cost.shape[0] - 1, cost.shape[1] - 1), geometric=False)

    print(f"\nMinimum-error boundary cut, best of {repeat}")
    print(f"{'input':<34} {'seams.py s':>11} {'MCP (3 moves) s':>16} {'route_through_array s':>22}")
    t_dp, _ = best_of(lambda: [minimum_error_boundary(s) for s in strips], repeat)
    t_mcp, _ = best_of(lambda: [mcp_seam(s) for s in strips], repeat)
    t_route, _ = best_of(lambda: [route(s) for s in strips], repeat)
    print(f"{'800 strips 64 x 11 (one quilt)':<34} {t_dp:11.3f} {t_mcp:16.3f} {t_route:22.3f}")
    t_dp, seam = best_of(lambda: minimum_error_boundary(energy), repeat)
    t_mcp, path = best_of(lambda: mcp_seam(energy), repeat)
    t_route, _ = best_of(lambda: route(energy), repeat)
    same = [c for _, c in path] == seam.tolist()
    print(f"{'one 512 x 512 energy map':<34} {t_dp:11.3f} {t_mcp:16.3f} {t_route:22.3f}   (same seam as MCP: {same})")
    t_cum, _ = best_of(lambda: cumulative_cost(energy), repeat)
    print(f"  of which cumulative_cost (the DP's forward pass) {t_cum:.3f} s")

    print("\nGraph cut (scipy.sparse.csgraph.maximum_flow, Dinic) on an n x n overlap, old | new constrained at the "
          "left | right edges, 3 channels")
    print(f"{'n':>5} {'pixels':>8} {'seconds':>8} {'with an old seam down the middle':>34}")
    for n in (64, 128, 256):
        old, new = rng.random((n, n, 3)), rng.random((n, n, 3))
        left, right = np.zeros((n, n), bool), np.zeros((n, n), bool)
        left[:, 0], right[:, -1] = True, True
        t, _ = best_of(graph_cut, repeat, old, new, old_mask=left, new_mask=right)
        labels = np.zeros((n, n), int)
        labels[:, n // 2:] = 1
        patches = np.stack([old, rng.random((n, n, 3))])
        composed = patches[labels, np.arange(n)[:, None], np.arange(n)[None, :]]
        t_seam, _ = best_of(graph_cut, repeat, composed, new, old_mask=left, new_mask=right, labels=labels,
                            patches=patches)
        print(f"{n:>5} {n * n:>8} {t:8.2f} {t_seam:34.2f}")


# --------------------------------------------------------------------------- figures


def _row(images, gap=6, height=None):
    """Images side by side on white, each padded to the tallest."""
    h = height or max(i.shape[0] for i in images)
    parts = []
    for image in images:
        image = image if image.ndim == 3 else np.repeat(image[..., None], 3, axis=2)
        image = np.pad(image, ((0, h - image.shape[0]), (0, 0), (0, 0)), constant_values=1.0)
        parts += [image, np.ones((h, gap, 3))]
    return np.concatenate(parts[:-1], axis=1)


def figures():
    import texsynth
    from texsynth.io import save_image
    from texsynth.patch._patch_sampling import patch_sampling
    from texsynth.patch._quilting import quilt, quilt_transfer

    static = ROOT / "docs" / "_static"
    static.mkdir(exist_ok=True)
    # Figure 1 of the paper: random blocks, matched blocks pasted over the overlap, the minimum-error cut
    for name, path, crop, block in (("brick", TEXTURES / "jcjohnson" / "brick.png", None, 32),
                                    ("text", TEXTURES / "lcv" / "text.pgm", 128, 36)):
        ex = load(path, crop)
        outs = [quilt(ex, 200, block=block, rng=1, **kw) for kw in ({"overlap": 0}, {"cut": False}, {})]
        save_image(static / f"quilting_figure1_{name}.png", _row([ex] + outs), overwrite=True)
    # transfer: a photograph rendered in bread, in text and in nuts (the paper's schedule, 3 passes, 16 -> 7 px)
    from skimage import data as skdata
    from skimage.transform import resize

    face = resize(skdata.camera(), (256, 256), anti_aliasing=True)
    textures = [load(TEXTURES / "jcjohnson" / "bread.png"), load(TEXTURES / "lcv" / "text.pgm", 160),
                load(TEXTURES / "lcv" / "nuts.pgm", 160)]
    save_image(static / "quilting_transfer.png",
               _row([face] + [quilt_transfer(t, face, block=16, rng=0) for t in textures]), overwrite=True)
    # the patch methods next to texture optimization and patchwork on the same inputs
    rows = []
    for path, crop in ((TEXTURES / "skimage" / "brick.png", 128), (TEXTURES / "embark" / "1.jpg", 128),
                       (TEXTURES / "lcv" / "nuts.pgm", 128)):
        ex = load(path, crop)
        rows.append(_row([ex, quilt(ex, 256, rng=0), patch_sampling(ex, 256, rng=0),
                          texsynth.graphcut_texture(ex, 256, rng=0), texsynth.optimize_texture(ex, 256, rng=0),
                          texsynth.patchwork(ex, 256, rng=0)]))
    width = max(r.shape[1] for r in rows)
    rows = [np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=1.0) for r in rows]
    save_image(static / "patch_methods_compared.png", np.concatenate(rows)[:-6], overwrite=True)
    # a minimum-error boundary cut drawn over its error surface
    from texsynth.core.seams import graph_cut, minimum_error_boundary

    ex = load(TEXTURES / "jcjohnson" / "bread.png")
    a, b = ex[:64, :24], ex[20:84, 60:84]
    error = ((a - b) ** 2).sum(-1)
    seam = minimum_error_boundary(error)
    shown = np.repeat((error / error.max())[..., None], 3, axis=2) ** 0.5
    shown[np.arange(64), seam] = (1.0, 0.2, 0.2)
    old, new = ex[:48, :48], ex[40:88, 50:98]
    keep = np.zeros((48, 48), bool)
    take = np.zeros((48, 48), bool)
    keep[:, :4], take[:, -4:] = True, True
    side, _ = graph_cut(old, new, old_mask=keep, new_mask=take)
    joined = np.where(side[..., None], new, old)
    outline = joined.copy()
    edge = (np.diff(side.astype(int), axis=1, prepend=side[:, :1]) != 0)
    outline[edge] = (1.0, 0.2, 0.2)
    big = [np.repeat(np.repeat(i, 3, 0), 3, 1) for i in (a, b, shown, old, new, outline)]
    save_image(static / "seams.png", _row(big), overwrite=True)
    # for looking: 1024^2 outputs from 256 px textures (not part of the docs)
    out_dir = ROOT / "benchmarks" / "output"
    out_dir.mkdir(exist_ok=True)
    inputs = {"bricks_1": load_scaled(PHOTOS / "bricks_1.png", 256), "pebbles_1": load_scaled(PHOTOS / "pebbles_1.png", 256),
              "cobblestones_1": load(PHOTOS / "cobblestones_1.png", 256),
              "stonewall_1": load_scaled(PHOTOS / "stonewall_1.png", 256),
              "text": load(TEXTURES / "lcv" / "text.pgm"), "water": load(TEXTURES / "embark" / "1.jpg", 256),
              "weave": load(TEXTURES / "rohitrango" / "t2.png"),
              "gravel": load(TEXTURES / "skimage" / "gravel.png", 256)}
    for name, ex in inputs.items():
        save_image(out_dir / f"quilt_{name}.png", quilt(ex, 1024, rng=0), overwrite=True)
        save_image(out_dir / f"patch_sampling_{name}.png", patch_sampling(ex, 1024, rng=0), overwrite=True)
        save_image(out_dir / f"quilt_tileable_{name}.png", np.tile(quilt(ex, 512, tileable=True, rng=0), (2, 2, 1)
                                                                    if ex.ndim == 3 else (2, 2)), overwrite=True)
    print(f"\nfigures in {static}, 1024^2 outputs in {out_dir}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--figures", action="store_true", help="write the docs' figures instead of timing")
    args = parser.parse_args()
    if args.figures:
        figures()
        return
    speed(args.repeat)
    seams(args.repeat)


if __name__ == "__main__":
    main()
