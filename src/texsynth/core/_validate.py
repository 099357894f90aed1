"""One place for input checks and image conversion.

Every public function of texsynth converts its array inputs here, once, at the
boundary; internal code can then rely on finite floating-point data in [0, 1]
with a known layout. Error messages name the parameter, what was received and
what would work.

Conventions (see ``docs/conventions.md``):

- images are ``(H, W)`` grey or ``(H, W, C)`` channels-last with ``C`` in 1..4;
  volumes are ``(D, H, W[, C])``, videos ``(T, H, W[, C])``;
- uint8, uint16 and bool are scaled to [0, 1]; float32 stays float32, every
  other accepted dtype becomes float64 (as scikit-image does);
- a ``str`` or ``pathlib.Path`` where an image is expected is read from the
  file (:func:`texsynth.io.load_image`; frames: :func:`texsynth.io.load_frames`);
- an alpha channel (``C == 4`` or ``C == 2``) is treated as one more channel:
  algorithms synthesise it like colour. Drop it with ``image[..., :3]`` first
  if it is not wanted.
"""

from __future__ import annotations

import contextlib
import contextvars
import numbers
import os
import reprlib

import numpy as np

__all__ = [
    "as_array",
    "check_group",
    "is_auto",
    "as_image",
    "as_float_array",
    "with_channels",
    "restore_channels",
    "as_binary_map",
    "as_rng",
    "as_size",
    "check_positive_int",
    "check_positive_float",
    "check_in_range",
    "check_bool",
    "check_choice",
    "check_memory",
    "available_memory",
    "memory_limit",
    "max_threads",
    "one_blas_thread",
]

_FLOAT_TOLERANCE = 1e-6


def as_array(data, name="image"):
    """``np.asarray`` with a TypeError naming ``name`` for None, strings and ragged sequences.

    >>> as_array(None, "exemplar")
    Traceback (most recent call last):
    ...
    TypeError: exemplar must be an array (uint8, uint16, bool or float in [0, 1]), got NoneType None
    """
    if data is None or isinstance(data, (str, bytes)):
        raise TypeError(
            f"{name} must be an array (uint8, uint16, bool or float in [0, 1]), got {type(data).__name__} "
            f"{reprlib.repr(data)}"
        )
    try:
        return np.asarray(data)
    except (ValueError, TypeError) as exc:
        raise TypeError(f"{name} must be an array with one number per pixel and channel: {exc}") from None


def as_float_array(array, name="image"):
    """Convert an array of any accepted dtype to float in [0, 1].

    Parameters
    ----------
    array : array_like
        uint8, uint16, bool or floating-point data. Floating-point data must
        already lie in [0, 1] (a tolerance of 1e-6 is clipped away).
    name : str
        Parameter name used in error messages.

    Returns
    -------
    numpy.ndarray
        float32 if the input was float32, float64 otherwise.

    Raises
    ------
    TypeError
        For an unsupported dtype (signed integers, complex, object).
    ValueError
        For an empty array, NaN or infinite values, or floats outside [0, 1].

    Examples
    --------
    >>> as_float_array(np.array([[0, 255]], dtype=np.uint8))
    array([[0., 1.]])
    """
    arr = as_array(array, name)
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape}); pass an image with at least one pixel")
    kind = arr.dtype
    if kind == np.bool_:
        return arr.astype(np.float64)
    if kind == np.uint8:
        return arr.astype(np.float64) / 255.0
    if kind == np.uint16:
        return arr.astype(np.float64) / 65535.0
    if np.issubdtype(kind, np.floating):
        out = arr.astype(np.float32 if kind == np.float32 else np.float64, copy=True)
        if not np.all(np.isfinite(out)):
            raise ValueError(f"{name} contains NaN or infinite values; replace them (e.g. np.nan_to_num) before calling")
        lo, hi = float(out.min()), float(out.max())
        if lo < -_FLOAT_TOLERANCE or hi > 1 + _FLOAT_TOLERANCE:
            hint = " (it looks like 0-255 data: divide by 255 or pass uint8)" if hi > 1.5 else ""
            raise ValueError(
                f"{name} is floating point with values in [{lo:.4g}, {hi:.4g}]; "
                f"float images must lie in [0, 1]{hint}"
            )
        np.clip(out, 0.0, 1.0, out=out)
        return out
    raise TypeError(
        f"{name} has dtype {kind}; pass uint8 (0-255), uint16 (0-65535), bool, "
        f"or float in [0, 1], e.g. {name}.astype(np.uint8) for 8-bit data"
    )


def as_image(image, name="image", *, spatial_dims=2, min_size=1):
    """Validate an image (or volume / video) and convert it to float in [0, 1].

    Parameters
    ----------
    image : array_like, str or os.PathLike
        ``spatial_dims`` spatial axes, optionally followed by a channel axis of
        length 1 to 4; or a file to read: an image (:func:`texsynth.io.load_image`)
        or, with ``spatial_dims=3``, frames (:func:`texsynth.io.load_frames`).
    name : str
        Parameter name used in error messages.
    spatial_dims : int
        2 for images, 3 for volumes and videos.
    min_size : int
        Smallest allowed extent of each spatial axis.

    Returns
    -------
    numpy.ndarray
        The converted array, same shape as the input.

    Examples
    --------
    >>> as_image(np.zeros((4, 5, 3), dtype=np.uint8)).shape
    (4, 5, 3)
    >>> as_image(np.zeros(5))
    Traceback (most recent call last):
    ...
    ValueError: image must have shape (H, W) or (H, W, C) with C in 1..4, got shape (5,)
    """
    if isinstance(image, (str, os.PathLike)):
        image = _read_file(image, name, spatial_dims)
    arr = as_array(image, name)
    axes = "(H, W)" if spatial_dims == 2 else "(D, H, W)"
    full = axes[:-1] + ", C)"
    ok = arr.ndim == spatial_dims or (arr.ndim == spatial_dims + 1 and 1 <= arr.shape[-1] <= 4)
    if not ok:
        raise ValueError(
            f"{name} must have shape {axes} or {full} with C in 1..4, got shape {arr.shape}"
        )
    spatial = arr.shape[:spatial_dims]
    if min(spatial) < min_size:
        raise ValueError(
            f"{name} has spatial shape {spatial}; every axis must be at least {min_size} pixels"
        )
    return as_float_array(arr, name)


def _read_file(path, name, spatial_dims):
    """An image (or, with 3 spatial axes, frames) given as a file name: read by texsynth.io; a missing or
    unreadable file is a FileNotFoundError or ValueError naming the parameter.

    The one import of a tool by the core (docs/architecture.md): imported here, on first use, since
    texsynth.io imports this module.
    """
    from ..io import load_frames, load_image

    try:
        return load_image(path) if spatial_dims == 2 else load_frames(path)
    except FileNotFoundError as exc:
        raise FileNotFoundError(f"{name}: {exc} (a str or pathlib.Path given for {name} is read as an image "
                                f"file; pass an array or an existing file)") from None
    except ValueError as exc:
        raise ValueError(f"{name}: {exc}") from None


def with_channels(image, spatial_dims=2):
    """Return ``(array with a channel axis, was_grey)``.

    >>> a, grey = with_channels(np.zeros((3, 4)))
    >>> a.shape, grey
    ((3, 4, 1), True)
    """
    if image.ndim == spatial_dims:
        return image[..., None], True
    return image, False


def restore_channels(image, was_grey):
    """Undo :func:`with_channels`: drop the channel axis of a grey result."""
    return image[..., 0] if was_grey else image


def as_binary_map(array, shape, name, meaning="where a pixel is known"):
    """A binary ``(H, W)`` map (a mask, a user's stroke) as bool: bool, or numbers that are all 0 or 1.

    ``meaning`` says what True stands for, in the error message.

    >>> as_binary_map([[0.0, 1.0]], (1, 2), "mask").tolist()
    [[False, True]]
    >>> as_binary_map([[0, 0.5]], (1, 2), "mask")
    Traceback (most recent call last):
    ...
    ValueError: mask must be binary (True/1 where a pixel is known, False/0 elsewhere); threshold it first, e.g. mask > 0.5
    """
    arr = np.asarray(array)
    if arr.ndim == 3 and arr.shape[-1] == 1:
        arr = arr[..., 0]
    if arr.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} (one value per pixel), got shape {np.shape(array)}")
    values = as_float_array(arr, name)
    if not np.all((values == 0) | (values == 1)):
        raise ValueError(f"{name} must be binary (True/1 {meaning}, False/0 elsewhere); "
                         f"threshold it first, e.g. {name} > 0.5")
    return values.astype(bool)


def as_rng(rng, name="rng"):
    """``np.random.default_rng`` with a clear error for wrong types.

    >>> bool(as_rng(0).integers(10) == as_rng(0).integers(10))
    True
    """
    if rng is None or isinstance(rng, (numbers.Integral, np.random.Generator, np.random.SeedSequence)):
        if isinstance(rng, numbers.Integral) and not isinstance(rng, bool) and rng < 0:
            raise ValueError(f"{name} must be a non-negative int seed, got {rng}")
        if isinstance(rng, bool):
            raise TypeError(f"{name} must be None, an int seed or a numpy.random.Generator, got bool")
        return np.random.default_rng(rng)
    raise TypeError(
        f"{name} must be None, an int seed or a numpy.random.Generator, got {type(rng).__name__}"
    )


def as_size(size, name="size", ndim=2):
    """Normalise an output size: an int means square (cube), a tuple is taken as is.

    >>> as_size(8)
    (8, 8)
    >>> as_size((4, 6))
    (4, 6)
    >>> as_size((0, 6))
    Traceback (most recent call last):
    ...
    ValueError: size must be positive integers (height, width), got (0, 6)
    """
    labels = {2: "(height, width)", 3: "(depth, height, width)"}.get(ndim, f"{ndim} integers")
    if isinstance(size, numbers.Integral) and not isinstance(size, bool):
        size = (int(size),) * ndim
    try:
        out = tuple(size)
    except TypeError:
        raise TypeError(f"{name} must be an int or a tuple {labels}, got {size!r}") from None
    if len(out) != ndim or not all(isinstance(s, numbers.Integral) and not isinstance(s, bool) for s in out):
        raise ValueError(f"{name} must be an int or {ndim} integers {labels}, got {size!r}")
    if min(out) < 1:
        raise ValueError(f"{name} must be positive integers {labels}, got {tuple(int(s) for s in out)}")
    return tuple(int(s) for s in out)


#: Most passes an iterative method accepts (``iterations``, ``passes``, ...): every pass is a full
#: sweep over the image, so more would run for days without changing a converged result.
MAX_ITERATIONS = 100_000


def check_positive_int(value, name, minimum=1, maximum=None):
    """Return ``value`` as int, raising if it is not an integer in ``minimum..maximum``."""
    if not isinstance(value, numbers.Integral) or isinstance(value, bool):
        raise TypeError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be at most {maximum} (each is a full pass over the image), got {value}")
    return int(value)


def check_positive_float(value, name, *, allow_zero=False, maximum=None):
    """Return ``value`` as float, raising unless it is finite and > 0 (>= 0), and at most ``maximum``.

    ``maximum`` bounds weights whose larger values mean nothing more and overflow in float32.
    """
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    bad = not np.isfinite(value) or value < 0 or (value == 0 and not allow_zero)
    if bad:
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be a finite number {bound}, got {value}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be at most {maximum:g}, got {value:g}")
    return value


def check_in_range(value, name, low, high, *, low_open=False, high_open=False):
    """Return ``value`` as float, raising unless it lies in the given interval."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    below = value <= low if low_open else value < low
    above = value >= high if high_open else value > high
    if not np.isfinite(value) or below or above:
        interval = f"{'(' if low_open else '['}{low}, {high}{')' if high_open else ']'}"
        raise ValueError(f"{name} must lie in {interval}, got {value}")
    return value


def is_auto(value):
    """True if ``value`` is ``"auto"``: the one spelling of "chosen by the method or its preset".

    Here for modules that must not load the search layer (which imports scipy.fft): the procedural
    textures. :func:`texsynth.core.search.is_auto` is the same test.

    >>> is_auto("auto"), is_auto(None), is_auto(4)
    (True, False, False)
    """
    return isinstance(value, str) and value == "auto"


def check_group(value, cls, name):
    """``value`` if it is an instance of the option group ``cls`` (a frozen dataclass), else a TypeError.

    >>> from texsynth.core.search import Search
    >>> check_group({"method": "exact"}, Search, "search")
    Traceback (most recent call last):
    ...
    TypeError: search must be a Search, e.g. search=Search(method=...), got dict {'method': 'exact'}
    """
    if isinstance(value, cls):
        return value
    first = next(iter(cls.__dataclass_fields__))
    raise TypeError(f"{name} must be a {cls.__name__}, e.g. {name}={cls.__name__}({first}=...), "
                    f"got {type(value).__name__} {reprlib.repr(value)}")


def check_bool(value, name):
    """``value`` if it is a bool (numpy's too), else a TypeError: ``tileable="no"`` must not mean True.

    >>> check_bool("no", "tileable")
    Traceback (most recent call last):
    ...
    TypeError: tileable must be True or False, got str 'no'
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {type(value).__name__} {reprlib.repr(value)}")


def check_choice(value, name, choices):
    """``value`` if it is one of ``choices`` (strings or ints, such as ``mode`` or ``spatial_dims``).

    A value of another type (a list, an array) is a TypeError, not numpy's "ambiguous truth value".

    >>> check_choice(["wrap"], "mode", ("valid", "wrap"))
    Traceback (most recent call last):
    ...
    TypeError: mode must be one of 'valid', 'wrap', got list ['wrap']
    """
    words = ", ".join(map(repr, choices))
    if not isinstance(value, (str, numbers.Integral)) or isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be one of {words}, got {type(value).__name__} {reprlib.repr(value)}")
    if value not in choices:
        raise ValueError(f"{name} must be one of {words}, got {value!r}")
    return value


_MEMORY_LIMIT = contextvars.ContextVar("texsynth_memory_limit", default=None)


@contextlib.contextmanager
def memory_limit(nbytes, holder):
    """Within the block, :func:`check_memory` allows at most ``nbytes`` (a Dask worker's share:
    ``holder`` names it in the messages), or what the machine has free if that is less."""
    token = _MEMORY_LIMIT.set((float(nbytes), holder))
    try:
        yield
    finally:
        _MEMORY_LIMIT.reset(token)


def available_memory():
    """Bytes of memory this process may still take: Linux's MemAvailable (else the physical memory),
    or less under an address-space limit (``ulimit -v``, ``resource.RLIMIT_AS``: what is left of it)
    or a :func:`memory_limit`. None if unknown."""
    free = _machine_memory()
    limit = _MEMORY_LIMIT.get()
    if limit is not None and (free is None or limit[0] < free):
        return limit[0]
    return free


def _machine_memory():
    free = None
    try:
        with open("/proc/meminfo") as f:
            free = next((int(line.split()[1]) * 1024 for line in f if line.startswith("MemAvailable:")), None)
    except (OSError, ValueError, IndexError):
        pass
    if free is None:
        try:
            free = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
        except (AttributeError, ValueError, OSError):  # pragma: no cover - not POSIX
            return None
    try:
        import resource

        limit = resource.getrlimit(resource.RLIMIT_AS)[0]
        if limit != resource.RLIM_INFINITY and limit >= 0:
            free = min(free, max(0, limit - _address_space()))  # the cap counts what the process already maps
    except (ImportError, AttributeError, ValueError, OSError):  # pragma: no cover - not POSIX
        pass
    return free


def _address_space():
    """Bytes of address space this process maps (Linux's VmSize), 0 if unknown."""
    try:
        with open("/proc/self/status") as f:
            return next((int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:")), 0)
    except (OSError, ValueError, IndexError):
        return 0


def _gib(nbytes):
    return f"{nbytes / 2**30:.1f} GiB"


def check_memory(nbytes, value, name="size", what="the output", also=None):
    """Refuse, before anything is allocated, work that needs more memory than the machine has free.

    Parameters
    ----------
    nbytes : float
        The estimate of the largest memory the call holds at once.
    value : object
        The value of the parameter that decides it (shown in the message).
    name : str
        That parameter's name (``"size"``).
    what : str
        What the memory is for, for the message.
    also : dict, optional
        Other parameters the estimate grows with (``{"n_frames": 100}``),
        named in the message too.

    Raises
    ------
    ValueError
        If ``nbytes`` exceeds the memory available (Linux's MemAvailable).

    Examples
    --------
    >>> check_memory(1e15, (10**7, 10**7))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: size=(10000000, 10000000) needs about 931322.6 GiB for the output, more than the ... GiB ...
    """
    free = available_memory()
    limit = _MEMORY_LIMIT.get()
    holder = limit[1] if limit is not None and free == limit[0] else "memory available"
    if free is not None and nbytes > free:
        names = [name] + list(also or {})
        given = ", ".join(f"{k}={v}" for k, v in [(name, value), *(also or {}).items()])
        raise ValueError(
            f"{given} {'need' if also else 'needs'} about {_gib(nbytes)} for {what}, more than the {_gib(free)} of "
            f"{holder}; pass a smaller {' or '.join(names)}"
        )


_THREADPOOLS = []  # one threadpoolctl controller, made on first use


def _threadpools():
    """The process's threadpoolctl controller, found once: finding the BLAS and OpenMP libraries reads
    the process's loaded libraries (about 1 ms), which hundreds of calls would pay each time."""
    if not _THREADPOOLS:
        from threadpoolctl import ThreadpoolController

        _THREADPOOLS.append(ThreadpoolController())
    return _THREADPOOLS[0]


def one_blas_thread():
    """A context in which BLAS runs on one thread: the library's one way to limit it.

    For many small products (per pixel, per pyramid band, per TPS solve) threads gain nothing, and a
    multi-threaded OpenBLAS spin-waits for its other thread on a busy machine (measured 10-100x
    slower on the 2-core VM under load). texsynth's own threads are capped by :func:`max_threads`.

    The BLAS libraries are looked up at each call (about 1 ms), so a BLAS that a package loaded
    since the last call (scipy's own OpenBLAS, say) is limited too.

    >>> with one_blas_thread():
    ...     _ = np.ones((3, 3)) @ np.ones((3, 3))
    """
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


def max_threads():
    """Threads a method may start: the cores, capped by the limits set on BLAS and OpenMP.

    ``OMP_NUM_THREADS=1`` or ``threadpoolctl.threadpool_limits(1)`` make it 1,
    so a user who limits the library's threads limits texsynth's own too.
    The BLAS and OpenMP libraries are found once (the first call) and their
    current limits read at every call.
    """
    cores = os.cpu_count() or 1
    limits = [pool["num_threads"] for pool in _threadpools().info() if pool.get("user_api") in ("blas", "openmp")]
    env = os.environ.get("OMP_NUM_THREADS", "")
    if env.isdigit() and int(env) > 0:
        limits.append(int(env))
    return max(1, min([cores] + limits))
