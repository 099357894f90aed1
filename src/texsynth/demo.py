"""The gallery that ``texsynth demo`` writes: every method on bundled sample textures.

The images are the ``demos`` of the methods in :mod:`texsynth.registry`: each
names the bundled sample it starts from and a small call that makes one image.
:func:`run_demo` writes one PNG per entry (and the exemplar next to it) and an
``index.html`` that shows them side by side.
"""

from __future__ import annotations

import html
import time
from pathlib import Path

from . import data
from .core.files import atomic_write
from .io import save_image
from .registry import Demo, demos

__all__ = ["Entry", "ENTRIES", "run_demo", "select_entries"]

_MARKER = ".texsynth-demo"


#: One gallery image (:class:`texsynth.registry.Demo`).
Entry = Demo

#: The gallery, in display order: every method's demos in :data:`texsynth.registry.METHODS`.
ENTRIES = demos()


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


def select_entries(names):
    """The gallery entries named in ``names`` (their slugs, as the demo's log prints them), in gallery order.

    Examples
    --------
    >>> [e.slug for e in select_entries(["wood", "marble"])]
    ['marble', 'wood']
    """
    import difflib

    names = [names] if isinstance(names, str) else list(names)
    known = [e.slug for e in ENTRIES]
    unknown = [n for n in names if n not in known]
    if unknown or not names:
        close = [m for n in unknown for m in difflib.get_close_matches(str(n), known, n=1)]
        hint = f" (did you mean {', '.join(map(repr, close))}?)" if close else ""
        raise ValueError(f"no gallery entry named {', '.join(map(repr, unknown)) or 'at all'}{hint}; "
                         f"choose among {', '.join(known)}")
    return [e for e in ENTRIES if e.slug in names]


def run_demo(output_dir="texsynth-demo", *, seed=0, entries=None, log=None):
    """Write the gallery into the folder ``output_dir`` and return the path of its ``index.html``.

    The folder is created if needed. It is refused if it already holds files
    that an earlier demo did not write, so nothing of the user's is replaced.
    """
    out = _prepare_folder(output_dir)
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
    atomic_write(index, lambda tmp: Path(tmp).write_text(page, encoding="utf-8"))
    return index


#: Gallery images of the video family: their input is a simulated clip, shown in the image itself.
CLIP_DEMOS = ("dynamic_texture_", "video_texture_", "graphcut_video_", "stylize_video_")


def _html(rows):
    cells = []
    for entry, seconds in rows:
        ex = (f'<img src="exemplar_{entry.sample}.png"><br>exemplar: {html.escape(entry.sample)}'
              if entry.sample else "a simulated clip (texsynth.data.clip), its first frame on the left"
              if entry.slug.startswith(CLIP_DEMOS) else "procedural (no exemplar)")
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
