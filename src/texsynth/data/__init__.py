"""Small real sample textures bundled with texsynth.

See ``ATTRIBUTION.md`` in this folder for sources and licences (MIT and
Apache-2.0 photographs from the Efros-Leung, Portilla-Simoncelli and
Embark Studios sample sets). ``bricks_hole`` is a colour image with an alpha
channel whose transparent disc is a hole to fill. :func:`clip` makes simulated clips for the video
methods (a candle flame, waves, raindrops): no photographed clip is bundled; :func:`volume` makes
example shapes for geometry synthesis (pebbles, a riveted plate); :func:`swatch` makes swatches of separate
geometry elements for mesh quilting (rivets in rows, pebbles, spikes) as ``(vertices, faces)``; :func:`btf`
renders example BTF samples (a stack of images under many light directions) from height fields (stones, bumps).

Examples
--------
>>> from texsynth import data
>>> data.names()
('bread', 'brick', 'bricks_hole', 'bumpy', 'ink', 'metal', 'nuts', 'reptile', 'text', 'water', 'wood')
>>> data.load("metal").shape
(256, 256)
"""

from __future__ import annotations

from pathlib import Path

from ..io import load_image
from ._clips import CLIPS, clip, clip_names
from ._shapes import VOLUMES, volume, volume_names
from ._swatches import SWATCHES, swatch, swatch_names
from ._btf import BTFS, btf, btf_names

__all__ = ["load", "names", "path", "clip", "clip_names", "CLIPS", "volume", "volume_names", "VOLUMES", "swatch",
           "swatch_names", "SWATCHES", "btf", "btf_names", "BTFS"]

_FILES = {
    "bread": "bread.png",
    "brick": "brick.png",
    "bricks_hole": "bricks_hole.png",
    "bumpy": "bumpy.png",
    "ink": "ink.png",
    "metal": "metal.pgm",
    "nuts": "nuts.pgm",
    "reptile": "reptil_skin.pgm",
    "text": "text.pgm",
    "water": "water.jpg",
    "wood": "wood.png",
}

#: Which samples are colour and which grey, and what kind of texture each is.
KINDS = {
    "bread": "colour, stochastic",
    "brick": "colour, structured",
    "bricks_hole": "colour with alpha, structured, a transparent hole to fill",
    "bumpy": "colour, stochastic",
    "ink": "colour, stochastic",
    "metal": "grey, stochastic",
    "nuts": "grey, objects",
    "reptile": "grey, structured",
    "text": "grey, text",
    "water": "colour, stochastic",
    "wood": "colour, structured",
}


def names():
    """Names of the bundled textures, sorted."""
    return tuple(sorted(_FILES))


def path(name):
    """Path of a bundled texture file."""
    if name not in _FILES:
        raise ValueError(f"name {name!r} is not a bundled texture; choose one of {', '.join(names())}")
    return Path(__file__).with_name(_FILES[name])


def load(name):
    """Load a bundled texture as float in [0, 1] (``(H, W)`` grey, ``(H, W, 3)`` colour or, for
    ``bricks_hole``, ``(H, W, 4)`` colour and alpha)."""
    return load_image(path(name))
