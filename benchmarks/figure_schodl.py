"""Video textures (Schödl et al. 2000) on a simulated candle flame: writes ``docs/_static/schodl_*``.

The clip is ``texsynth.data.clip("flame", 300)`` (simulated; no video is bundled): a 128x128 colour candle whose flame sways, stretches and
flickers with three incommensurate periods (41, 17.3 and 9.7 frames) while a turbulent pattern rises
through it (64-frame period), so no frame ever comes back exactly and every jump is a compromise (no camera
noise, to keep the GIF small). Writes

- ``schodl_strips.png``: (1) the input, every 30th frame; (2) a 10 s loop (300 frames at 30 fps) across
  its wrap, its last 5 frames then its first 5, hard cut (``crossfade=0``); (3) the same with the default
  4-frame cross-fade; (4) random play around a jump, the jump between the 5th and 6th frame;
- ``schodl_matrices.png``: the filtered distances ``D'`` (dark: similar; white: undefined, a tap outside
  the clip), the future costs ``D''`` (log) and the pruned probabilities ``P''`` (log, white 1, black 1e-6 or
  pruned; each entry drawn 3 px wide), with the loop's jumps marked in red on ``D'``;
- ``schodl_loop.gif``: the loop, played at 30 fps (it wraps seamlessly);

and prints the jump costs against the clip's consecutive-frame distances.

    python benchmarks/figure_schodl.py
"""

from pathlib import Path

import numpy as np

from texsynth import data
from texsynth.io import save_frames, save_image
from texsynth.video import video_texture

HERE = Path(__file__).resolve().parent
STATIC = HERE.parent / "docs" / "_static"
FPS = 30


#: The flame's part of the frame, shown in the strips (twice enlarged) and the GIF.
CROP = (slice(24, 112), slice(30, 98))


def strip(frames, gap=4, crop=True):
    """Frames side by side with white gaps (cropped to the flame and enlarged twice)."""
    if crop:
        frames = [np.repeat(np.repeat(f[CROP], 2, 0), 2, 1) for f in frames]
    h = frames[0].shape[0]
    parts = []
    for f in frames:
        parts += [f, np.ones((h, gap, 3))]
    return np.concatenate(parts[:-1], 1)


def main():
    clip = data.clip("flame", 300, 128, rng=0)
    T = len(clip)
    n = 10 * FPS
    loop_cut, info = video_texture(clip, n, loop=True, crossfade=0, return_info=True)
    loop_fade = video_texture(clip, n, loop=True)
    play, pinfo = video_texture(clip, 600, rng=1, return_info=True)
    D = info.distances
    consecutive = D[np.arange(T - 1), np.arange(1, T)]
    seq, jumps = info.sequence, info.jumps
    jump_d = D[np.minimum(seq[jumps] + 1, T - 1), seq[(jumps + 1) % n]]
    rest = np.triu(D, 2)
    print(f"clip {clip.shape}; loop of {n} frames ({n / FPS:g} s at {FPS} fps): primitive loops "
          f"{[(int(a), int(b), int(a - b + 1)) for a, b in info.loops]} (source, destination, length)")
    print(f"  jumps' distances D_(i+1, j): {np.round(jump_d, 2).tolist()}")
    print(f"  consecutive frames: median {np.median(consecutive):.2f}, max {consecutive.max():.2f}; "
          f"a random pair of frames: median {np.median(rest[rest > 0]):.2f}")
    print(f"  worst jump / median consecutive: {jump_d.max() / np.median(consecutive):.2f}")
    pj = pinfo.jumps
    pd = D[np.minimum(pinfo.sequence[pj] + 1, T - 1), pinfo.sequence[pj + 1]]
    print(f"random play, 600 frames: {len(pj)} jumps, worst D_(i+1, j) {pd.max():.2f}, sigma {pinfo.sigma:.3g}, "
          f"{pinfo.sweeps} sweeps; frames played: {np.unique(pinfo.sequence).size} of {T}, dead ends (infinite "
          f"future) played: {int(np.isinf(pinfo.future_costs.min(1))[pinfo.sequence].sum())}")

    wrap = np.r_[n - 5:n, 0:5]
    t0 = int(pj[len(pj) // 2]) - 4
    rows = [strip(clip[::30]), strip(loop_cut[wrap]), strip(loop_fade[wrap]), strip(play[t0:t0 + 10])]
    width = max(r.shape[1] for r in rows)
    rows = [np.pad(r, ((0, 0), (0, width - r.shape[1]), (0, 0)), constant_values=1) for r in rows]
    figure = np.concatenate([p for r in rows for p in (r, np.ones((8, width, 3)))][:-1], 0)
    save_image(STATIC / "schodl_strips.png", figure, overwrite=True)

    def show(m, log=False):
        v = np.where(np.isfinite(m), m, np.nan)
        v = np.log1p(v) if log else v
        low, high = np.nanpercentile(v, [1, 99])
        v = np.clip((v - low) / (high - low), 0, 1)
        return np.repeat(np.nan_to_num(v, nan=1.0)[..., None], 3, -1)

    dp = show(info.filtered_distances)
    for a, b in info.loops:  # the loop's jumps a -> b, at (a + 1, b) of D'
        dp[max(a - 2, 0):a + 5, max(b - 3, 0):b + 4] = [1, 0, 0]
    p = info.probabilities
    level = 1 - np.clip(np.log10(np.where(p > 0, p, 1e-6)) / -6, 0, 1)  # white: 1, black: 1e-6 or pruned
    from scipy.ndimage import maximum_filter

    pimg = np.repeat(maximum_filter(level * (p > 0), size=3)[..., None], 3, -1)  # each kept entry drawn 3 px wide
    mats = strip([dp, show(info.future_costs, log=True), pimg], gap=8, crop=False)
    save_image(STATIC / "schodl_matrices.png", mats, overwrite=True)
    path = save_frames(STATIC / "schodl_loop.gif", loop_fade[(slice(None),) + CROP], fps=FPS, overwrite=True)
    print(f"wrote {STATIC / 'schodl_strips.png'}, {STATIC / 'schodl_matrices.png'}, {path} "
          f"({path.stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    main()
