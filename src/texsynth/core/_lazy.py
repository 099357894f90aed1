"""Lazy package namespaces (PEP 562): a name's module is imported on first use.

``import texsynth`` then costs almost nothing; ``texsynth.optimize_texture``
imports the optimization family when it is first looked up, and a submodule
such as ``texsynth.metrics`` likewise.
"""

from __future__ import annotations

import importlib

__all__ = ["attach"]


def attach(package, submodules=(), names=None):
    """``(__getattr__, __dir__, __all__)`` for a package whose names load lazily.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    submodules : sequence of str
        Submodules reachable as attributes (``package.sub``).
    names : dict, optional
        ``{name: module}``: public names defined in other modules (absolute
        or relative to ``package``).

    Returns
    -------
    __getattr__, __dir__ : callable
        To assign in the package's ``__init__``.
    __all__ : list of str
        The names, then the submodules.
    """
    names = dict(names or {})
    submodules = tuple(submodules)

    def __getattr__(name):
        if name in names:
            value = getattr(importlib.import_module(names[name], package), name)
        elif name in submodules:
            value = importlib.import_module(f"{package}.{name}")
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        importlib.import_module(package).__dict__[name] = value  # later lookups skip __getattr__
        return value

    def __dir__():
        return sorted(set(names) | set(submodules) | set(importlib.import_module(package).__dict__))

    return __getattr__, __dir__, list(names) + list(submodules)
