"""The gallery that ``texsynth demo`` writes: every method on bundled sample textures.

Each :class:`Entry` names a method, the bundled sample it starts from and a
small call that makes one image. :func:`run_demo` writes one PNG per entry
(and the exemplar next to it) and an ``index.html`` that shows them side by
side. Sizes are small so the whole gallery takes about a minute on 2 cores.
"""

from __future__ import annotations

import html
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from . import data
from .io import _atomic_write, save_image

__all__ = ["Entry", "ENTRIES", "run_demo"]

_MARKER = ".texsynth-demo"


@dataclass(frozen=True)
class Entry:
    """One gallery image.

    ``make(exemplar, seed)`` returns the result image; ``sample`` is the
    bundled texture it starts from (None for procedural entries).
    """

    slug: str
    title: str
    paper: str
    sample: str | None
    make: Callable


def _heeger_bergen(exemplar, seed):
    from .statistical import heeger_bergen

    return heeger_bergen(exemplar, (192, 192), rng=seed)


def _patchwork(grid_spacing):
    def make(exemplar, seed):
        from .patch import patchwork

        return patchwork(exemplar, (256, 256), grid_spacing=grid_spacing, tileable=True, rng=seed)

    return make


def _portilla_simoncelli(exemplar, seed):
    from .statistical import portilla_simoncelli

    return portilla_simoncelli(exemplar, (128, 128), iterations=30, rng=seed)


def _procedural(name, **options):
    def make(exemplar, seed):
        from . import procedural

        return getattr(procedural, name)((192, 192), rng=seed, **options)

    return make


def _optimize(exemplar, seed):
    from .optimization import optimize_texture

    return optimize_texture(exemplar, (128, 128), rng=seed)


def _optimize_complete(exemplar, seed):
    from .optimization import optimize_texture

    return optimize_texture(exemplar[:96, :96], (144, 144), completeness_weight=1.0, copy_limit=0.2, rng=seed)


def _animate(exemplar, seed):
    from .core import flows
    from .optimization import animate_texture

    frames = animate_texture(exemplar[:96, :96], flows.rotation((96, 96), 0.06), frames=8, rng=seed)
    return _side_by_side([frames[0], frames[3], frames[7]])


def _pixels(exemplar, seed):
    from .pixel import synthesize_pixels

    return synthesize_pixels(exemplar[:64, :64], (160, 160), rng=seed)


def _mixture(exemplar, seed):
    import numpy as np

    from .pixel import mix_textures

    ramp = np.broadcast_to(np.linspace(0.0, 1.0, 192), (96, 192))
    other = data.load("bread")[:64, :64]
    return mix_textures([exemplar[:64, :64], other], (96, 192), weights=[1.0 - ramp, ramp], rng=seed)


def _interpolate(exemplar, seed):
    from .optimization import interpolate_textures

    other = data.load("bumpy")[:64, :64]
    return interpolate_textures(exemplar[:64, :64], other, 0.5, size=(64, 64), stages=((2, 17), (1, 17)), rng=seed)


def _side_by_side(images, gap=4):
    """Images of one height next to each other, separated by white gaps."""
    import numpy as np

    white = np.ones((images[0].shape[0], gap) + images[0].shape[2:])
    parts = [images[0]]
    for image in images[1:]:
        parts += [white, image]
    return np.concatenate(parts, axis=1)


def _solid(exemplar, seed):
    from .pixel import synthesize_solid

    volume = synthesize_solid(exemplar[:64, :64], 32, rng=seed)
    # three faces of the cube, one per axis: each should look like the exemplar
    return _side_by_side([volume[0], volume[:, 0], volume[:, :, 0]])


def _patchwork_video(exemplar, seed):
    import numpy as np

    from .patch import patchwork_video

    clip = np.stack([exemplar[:128, 4 * t:4 * t + 128] for t in range(16)])  # a window drifting over the photo
    video = patchwork_video(clip, (128, 128), 12, grid_spacing=32, rng=seed)
    return _side_by_side([video[0], video[5], video[11]])


def _entries():
    """The gallery, in display order."""
    hb = "Heeger & Bergen, SIGGRAPH 1995 (doi:10.1145/218380.218446)"
    pw = "Harrison, Monash University technical report 2002 (patchwork texture synthesis)"
    ps = "Portilla & Simoncelli, IJCV 2000 (doi:10.1023/A:1026553619983)"
    perlin = "Perlin, SIGGRAPH 1985 / 2002 (doi:10.1145/325165.325247)"
    return [
        Entry("marble", "Perlin marble: sin(x + turbulence) through a colour map", perlin, None,
              _procedural("marble")),
        Entry("wood", "Solid wood rings: sin(radius + turbulence)", perlin, None, _procedural("wood")),
        Entry("reaction_diffusion", "Turk reaction-diffusion spots", "Turk, SIGGRAPH 1991 (doi:10.1145/122718.122749)",
              None, _procedural("reaction_diffusion", steps=6000)),
        Entry("reaction_diffusion_stripes", "Turk's two-chemical system far above the Turing threshold: stripes",
              "Turk, SIGGRAPH 1991 (doi:10.1145/122718.122749)", None,
              _procedural("reaction_diffusion", pattern="stripes", steps=10000)),
        Entry("gray_scott_mazes", "Gray-Scott reaction-diffusion, 'mazes' preset",
              "Pearson, Science 1993 (doi:10.1126/science.261.5118.189)", None,
              _procedural("gray_scott", preset="mazes", steps=6000)),
        Entry("pixels_bread", "Wei-Levoy pixel synthesis (scanline, 3 levels, causal 5x5 neighbourhoods)",
              "Wei & Levoy, SIGGRAPH 2000 (doi:10.1145/344779.345009)", "bread", _pixels),
        Entry("mix_brick_bread", "Wei texture mixture, ramp weights: brick (left) turning into bread (right)",
              "Wei, SIGGRAPH 2002 sketch (texture synthesis from multiple sources)", "brick", _mixture),
        Entry("solid_bread", "Wei solid texture from one 2-D view: three faces of a 32^3 cube (x, y and z slices)",
              "Wei, SIGGRAPH 2002 sketch (texture synthesis from multiple sources)", "bread", _solid),
        Entry("optimize_bread", "Kwatra texture optimization (EM + IRLS, 3 levels, sizes 32/16/8)",
              "Kwatra et al., SIGGRAPH 2005 (doi:10.1145/1073204.1073263)", "bread", _optimize),
        Entry("optimize_text_complete", "Kwatra texture optimization with the completeness term of the "
              "bidirectional similarity and a copy limit (completeness_weight=1, copy_limit=0.2): all of the "
              "96x96 exemplar, in pieces of at most a third of it",
              "Kwatra et al., SIGGRAPH 2005; Simakov et al., CVPR 2008 (doi:10.1109/CVPR.2008.4587842)", "text",
              _optimize_complete),
        Entry("animate_bumpy", "Kwatra flow-guided animation, rotation 0.06 rad/frame: frames 1, 4 and 8 "
              "(elements follow the flow; they soften over the frames)",
              "Kwatra et al., SIGGRAPH 2005, Section 4.1", "bumpy", _animate),
        Entry("interpolate_brick_bumpy", "Ruiters texture interpolation, alpha = 0.5: brick halfway to bumpy plaster "
              "(small: 64x64, stages (2, 17), (1, 17))",
              "Ruiters, Schnabel & Klein, CGF 2010 (doi:10.1111/j.1467-8659.2010.01739.x)", "brick", _interpolate),
        Entry("patchwork_water", "Harrison patchwork, tileable (grid 64, f = 6)", pw, "water", _patchwork(64)),
        Entry("patchwork_video_water", "Harrison video patchwork: frames 1, 6 and 12 of a looping 12-frame "
              "video from a 16-frame input clip (the water photograph drifting sideways: no video texture is "
              "bundled)", pw, "water", _patchwork_video),
        Entry("patchwork_bread", "Harrison patchwork, tileable (grid 24, f = 6)", pw, "bread", _patchwork(24)),
        Entry("heeger_bergen_metal", "Heeger-Bergen: stochastic texture (works)", hb, "metal", _heeger_bergen),
        Entry("heeger_bergen_bread", "Heeger-Bergen: colour by PCA (works)", hb, "bread", _heeger_bergen),
        Entry("heeger_bergen_text", "Heeger-Bergen: structured texture (fails: no letters)", hb, "text",
              _heeger_bergen),
        Entry("portilla_simoncelli_reptile", "Portilla-Simoncelli: structured texture", ps, "reptile",
              _portilla_simoncelli),
        Entry("portilla_simoncelli_text", "Portilla-Simoncelli: text (letter-like strokes, no words)", ps, "text",
              _portilla_simoncelli),
    ]


ENTRIES = _entries()


def _prepare_folder(out):
    out = Path(out)
    if out.exists():
        if not out.is_dir():
            raise FileExistsError(f"--out {str(out)!r} is a file; choose a folder name")
        if any(out.iterdir()) and not (out / _MARKER).exists():
            raise FileExistsError(
                f"--out {str(out)!r} exists and holds files that texsynth demo did not write; "
                "choose another folder"
            )
    out.mkdir(parents=True, exist_ok=True)
    (out / _MARKER).write_text("written by texsynth demo; the demo may overwrite files here\n")
    return out


def run_demo(out="texsynth-demo", *, seed=0, entries=None, log=None):
    """Write the gallery into ``out`` and return the path of its ``index.html``.

    The folder is created if needed. It is refused if it already holds files
    that an earlier demo did not write, so nothing of the user's is replaced.
    """
    out = _prepare_folder(out)
    rows = []
    for entry in ENTRIES if entries is None else entries:
        exemplar = data.load(entry.sample) if entry.sample else None
        start = time.perf_counter()
        result = entry.make(exemplar, seed)
        seconds = time.perf_counter() - start
        if entry.sample:
            save_image(out / f"exemplar_{entry.sample}.png", exemplar, overwrite=True)
        save_image(out / f"{entry.slug}.png", result, overwrite=True)
        rows.append((entry, seconds))
        if log:
            log(f"{entry.slug:<32} {seconds:6.1f} s")
    index = out / "index.html"
    page = _html(rows)
    _atomic_write(index, lambda tmp: Path(tmp).write_text(page, encoding="utf-8"))
    return index


def _html(rows):
    cells = []
    for entry, seconds in rows:
        ex = (f'<img src="exemplar_{entry.sample}.png"><br>exemplar: {html.escape(entry.sample)}'
              if entry.sample else "procedural (no exemplar)")
        cells.append(
            f"<tr><td>{ex}</td><td><img src=\"{entry.slug}.png\"></td>"
            f"<td><b>{html.escape(entry.title)}</b><br>{html.escape(entry.paper)}<br>{seconds:.1f} s</td></tr>"
        )
    return (
        "<!doctype html><html><head><meta charset='utf-8'><title>texsynth demo</title>"
        "<style>body{font-family:sans-serif}td{vertical-align:top;padding:8px}"
        "img{image-rendering:pixelated;max-width:384px}</style></head><body>"
        "<h1>texsynth demo</h1><p>Exemplar (bundled sample) and result, side by side.</p>"
        "<table>" + "".join(cells) + "</table></body></html>\n"
    )
