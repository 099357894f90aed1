"""Deprecations: old module paths and old parameter names keep working for one release.

Every deprecated spelling warns with a :class:`DeprecationWarning` that names
the new spelling, so a user can fix the call from the message alone.
"""

from __future__ import annotations

import functools
import importlib
import importlib.machinery
import inspect
import sys
import types
import warnings

__all__ = ["DeprecatedModule", "install_module_aliases", "renamed_parameters", "TotalSeconds", "warn"]


def warn(message, stacklevel=3):
    """Emit a :class:`DeprecationWarning` pointing at the user's call (two frames up by default)."""
    warnings.warn(message, DeprecationWarning, stacklevel=stacklevel)


class DeprecatedModule(types.ModuleType):
    """An old module path: every attribute comes from the new module, with a warning.

    Parameters
    ----------
    old : str
        The old dotted path, e.g. ``"texsynth.multisource"``.
    new : str
        The module that now holds the code (private names are found there too).
    public : str
        The public spelling to recommend, e.g. ``"texsynth.pixel"``.
    renamed : dict, optional
        ``{old_name: "module.new_name"}`` for names that moved elsewhere.
    """

    def __init__(self, old, new, public, renamed=None):
        super().__init__(old, f"Deprecated alias of {public}.")
        self.__spec__ = importlib.machinery.ModuleSpec(old, None)  # importlib.util.find_spec works on it
        self._new, self._public, self._renamed = new, public, dict(renamed or {})

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        if name in self._renamed:
            module_name, _, new_name = self._renamed[name].rpartition(".")
            value = getattr(importlib.import_module(module_name), new_name)
            warn(f"{self.__name__}.{name} is deprecated; use {self._renamed[name]} instead", stacklevel=3)
            return value
        value = getattr(importlib.import_module(self._new), name)
        where = self._new if name.startswith("_") else self._public
        warn(f"{self.__name__} is deprecated; use {where}.{name} instead", stacklevel=3)
        return value

    def __dir__(self):
        return dir(importlib.import_module(self._new))


def install_module_aliases(aliases):
    """Register ``{old: (new, public[, renamed])}`` as importable deprecated modules (nothing is imported yet)."""
    for old, spec in aliases.items():
        sys.modules.setdefault(old, DeprecatedModule(old, *spec))


def renamed_parameters(**renames):
    """Decorator: accept old keyword names ``old=new`` for one release, with a warning.

    The old name's value is passed on under the new name (``old=(new,
    convert)`` converts it first); giving both is an error.
    ``func.renamed_parameters`` keeps ``{old: new}`` (the command line reads
    it to accept the old option names too).

    Examples
    --------
    >>> @renamed_parameters(frames="n_frames")
    ... def f(*, n_frames=1):
    ...     return n_frames
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     f(frames=3), str(caught[0].message)
    (3, 'f(frames=...) is deprecated; use n_frames=... instead')
    """
    table = {old: spec if isinstance(spec, tuple) else (spec, None) for old, spec in renames.items()}

    def decorate(func):
        params = inspect.signature(func).parameters
        for new, _ in table.values():
            if new not in params:
                raise TypeError(f"{func.__qualname__} has no parameter {new!r} to rename to")

        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            for old, (new, convert) in table.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{func.__name__}() got both {old}= (deprecated) and {new}=; pass only {new}=")
                    value = kwargs.pop(old)
                    shown = "..." if convert is None else repr(convert(value))
                    warn(f"{func.__name__}({old}=...) is deprecated; use {new}={shown} instead")
                    kwargs[new] = value if convert is None else convert(value)
            return func(*args, **kwargs)

        wrapper.renamed_parameters = {**getattr(func, "renamed_parameters", {}),
                                      **{old: new for old, (new, _) in table.items()}}
        wrapper.renamed_converters = {**getattr(func, "renamed_converters", {}),
                                      **{old: convert for old, (_, convert) in table.items() if convert}}
        return wrapper

    return decorate


class TotalSeconds(float):
    """A total wall time that still answers the per-part lookups of 0.1 (``info.seconds["synthesis"]``).

    Since 0.2 every info object has ``seconds`` (the total, a float) and
    ``stage_seconds`` (the parts, a dict). Where ``seconds`` used to be the
    dict, indexing it still works for one release, with a warning.

    Examples
    --------
    >>> t = TotalSeconds(3.0, {"a": 1.0, "b": 2.0}, "Info")
    >>> float(t), t + 1
    (3.0, 4.0)
    """

    def __new__(cls, total, parts, owner):
        obj = super().__new__(cls, total)
        obj._parts, obj._owner = parts, owner
        return obj

    def _dict(self):
        warn(f"{self._owner}.seconds is the total wall time (a float) since 0.2; use {self._owner}.stage_seconds "
             "instead for the parts")
        return self._parts

    def __getitem__(self, key):
        return self._dict()[key]

    def keys(self):
        return self._dict().keys()

    def values(self):
        return self._dict().values()

    def items(self):
        return self._dict().items()

    def get(self, key, default=None):
        return self._dict().get(key, default)
