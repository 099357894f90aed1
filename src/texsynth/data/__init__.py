"""Small real sample textures bundled with texsynth.

See ``ATTRIBUTION.md`` in this folder for sources and licences (MIT and
Apache-2.0 photographs from the Efros-Leung, Portilla-Simoncelli and
Embark Studios sample sets).

Examples
--------
>>> from texsynth import data
>>> data.names()
('bread', 'brick', 'bumpy', 'metal', 'reptile', 'text', 'water', 'wood')
>>> data.load("metal").shape
(256, 256)
"""

from __future__ import annotations

from pathlib import Path

from ..io import load_image

__all__ = ["load", "names", "path"]

_FILES = {
    "bread": "bread.png",
    "brick": "brick.png",
    "bumpy": "bumpy.png",
    "metal": "metal.pgm",
    "reptile": "reptil_skin.pgm",
    "text": "text.pgm",
    "water": "water.jpg",
    "wood": "wood.png",
}

#: Which samples are colour and which grey, and what kind of texture each is.
KINDS = {
    "bread": "colour, stochastic",
    "brick": "colour, structured",
    "bumpy": "colour, stochastic",
    "metal": "grey, stochastic",
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
    """Load a bundled texture as float in [0, 1] (``(H, W)`` grey or ``(H, W, 3)`` colour)."""
    return load_image(path(name))
