"""texsynth: example-based texture synthesis on one shared numpy layer.

The public API is listed once, in ``__all__``; see ``docs/`` and README.md.
"""

from . import data, io

__version__ = "0.1.0"

__all__ = ["data", "io", "__version__"]
