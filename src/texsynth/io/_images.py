"""Single images: load_image, save_image, to_uint, the bits of a file, and float ranges (normalize_range,
restore_range)."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np

from ..core._validate import as_array, as_float_array, as_image, check_bool, check_memory
from ..core.files import as_path, atomic_write, prepare_target
from ._formats import (EIGHT_BIT, EXR, EXR_MAGIC, HALF_MAX, NO_ALPHA, SIXTEEN_BIT, TIFF_MAGIC, VIDEO, check_bits,
                       check_tiff_size, exr_bits, file_head, holds_at_most_16_bits, is_cmyk, openexr, png_header, read,
                       read_exr, read_png16, short, supported_integers, write_exr, write_png16)


def image_bits(path):
    """Bits per sample of an image file: 8, 16 or 32 (floating point).

    Parameters
    ----------
    path : str or os.PathLike
        An image file that :func:`load_image` reads.

    Returns
    -------
    int
        16 for 16-bit PNG, PGM/PPM and TIFF files and for half-float EXR
        files, 32 for floating-point TIFF and float32 EXR files, 8 for
        everything else (palette, 1-bit and 8-bit files, TGA).

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike.
    ValueError
        If the file cannot be read as an image.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     image_bits(save_image(d + "/c.png", np.zeros((2, 2, 3)), bits=16))
    16
    """
    path = as_path(path)
    header = png_header(path)
    if header is not None:
        return 16 if header[2] == 16 else 8
    if file_head(path, 4) == EXR_MAGIC:
        return exr_bits(path)
    try:
        kind = iio.improps(path).dtype
    except Exception as exc:
        raise ValueError(f"cannot read {str(path)!r} as an image: {exc}") from None
    if np.issubdtype(kind, np.floating):
        return 32
    if kind == np.uint16 or (kind == np.int32 and holds_at_most_16_bits(path)):  # Pillow: 16-bit PGM as int32
        return 16
    return 8


def load_image(path, *, normalize=False):
    """Read an image file as float in [0, 1].

    Parameters
    ----------
    path : str or os.PathLike
        Any format imageio reads (PNG, JPEG, PGM/PPM, TIFF, BMP, TGA, ...),
        and OpenEXR (``.exr``, with the ``exr`` extra).
    normalize : bool
        Float files whose values leave [0, 1] (heights, displacement, HDR
        colour) are refused unless this is True; then the image is scaled
        into [0, 1] by the file's minimum and maximum (:func:`normalize_range`)
        and returned with that range, for :func:`restore_range`.

    Returns
    -------
    image : numpy.ndarray
        ``(H, W)`` for grey files, ``(H, W, C)`` otherwise (alpha kept as the
        last channel), float64 in [0, 1] (float32 for float32 TIFFs and EXR
        files).
    value_range : (float, float)
        Only with ``normalize=True``: the ``(low, high)`` that 0 and 1 stand
        for, ``(0.0, 1.0)`` for every file already in [0, 1] (integer files,
        and float files inside it, which are returned unchanged).

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike.
    FileNotFoundError
        If ``path`` does not exist or is a folder.
    ValueError
        If the file cannot be read as an image, holds several frames, holds
        pixels of an integer type without an agreed white level, holds float
        values outside [0, 1] and ``normalize`` is False, or claims
        more pixels than Pillow's limit against decompression bombs
        (``2 * PIL.Image.MAX_IMAGE_PIXELS``, checked from the header for
        TIFF files as Pillow does for PNG and JPEG).
    ImportError
        For a ``.exr`` file without the OpenEXR package
        (``python -m pip install '.[exr]'`` in a checkout).

    Notes
    -----
    Pixel types are converted by the rule of the whole library: uint8 is
    divided by 255, uint16 by 65535, and float data must lie in [0, 1].
    16-bit PNG and PGM/PPM files, which Pillow decodes as int32 with values
    0-65535, are read as the 16-bit files they are (their format allows
    unsigned samples of at most 16 bits only, so the white level is 65535).
    Any other signed or 32/64-bit integer file (e.g. an int32 TIFF) is refused
    with a ValueError: its white level is not stored in the file (the full
    type range, the data maximum and 4095 for 12-bit sensors are all in use),
    and a guess would be a silently wrong image.

    CMYK files (JPEG or TIFF from print workflows) are converted to RGB with
    Pillow's conversion, rather than read as 4 channels whose last one would
    pass for alpha.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = save_image(d + "/ramp.png", np.linspace(0, 1, 12).reshape(3, 4))
    ...     image = load_image(path)
    >>> image.shape, image.dtype, image.max()
    ((3, 4), dtype('float64'), np.float64(1.0))

    A height map in metres, saved as a float TIFF, comes back scaled with its
    range:

    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = save_image(d + "/h.tif", np.array([[-2.0, 0.0], [1.0, 6.0]]), bits=32)
    ...     unit, value_range = load_image(path, normalize=True)
    >>> unit.tolist(), value_range
    ([[0.0, 0.25], [0.375, 1.0]], (-2.0, 6.0))
    """
    path = as_path(path)
    normalize = check_bool(normalize, "normalize")
    if path.is_dir():
        raise FileNotFoundError(f"path {str(path)!r} is a folder, not an image file; load_frames reads a folder of frames")
    if not path.is_file():
        raise FileNotFoundError(f"path {str(path)!r} does not exist or is not a file")
    header = png_header(path)
    if file_head(path, 4) in TIFF_MAGIC:
        check_tiff_size(path)
    if header is not None and header[2] == 16 and header[3] in (2, 4, 6):  # 16-bit colour: Pillow reads 8 bits
        data = read_png16(path, header)
    elif file_head(path, 4) == EXR_MAGIC or path.suffix.lower() in EXR:
        data = read_exr(path)
    else:
        data = read(path)
    if data.ndim == 3 and data.shape[-1] == 4 and is_cmyk(path):
        data = read(path, plugin="pillow", mode="RGB")
    if (data.ndim == 3 and data.shape[-1] > 4 and data.shape[0] > 1) or (data.ndim == 4 and data.shape[0] > 1):
        raise ValueError(f"{str(path)!r} holds {data.shape[0]} frames; use load_frames for animations")
    if data.ndim == 4 and data.shape[0] == 1:
        data = data[0]
    data = supported_integers(data, path)
    name = f"image in {path.name}"
    if np.issubdtype(data.dtype, np.floating) and data.size and np.all(np.isfinite(data)):
        lo, hi = float(data.min()), float(data.max())
        if (lo < -_RANGE_TOLERANCE or hi > 1 + _RANGE_TOLERANCE) and not normalize:
            raise ValueError(
                f"{str(path)!r} holds float values in [{lo:.6g}, {hi:.6g}], outside [0, 1] (a height, displacement "
                "or HDR file?); read it with texsynth.io.load_image(path, normalize=True), which scales it into "
                "[0, 1] and returns its range for texsynth.io.restore_range (the command line does this for "
                "its inputs and --channels)"
            )
    if normalize:
        return _normalize(data, None, name)
    return as_image(data, name=name)


# --------------------------------------------------------------------------- #
# conversion
# --------------------------------------------------------------------------- #
def to_uint(image, bits=8):
    """Convert image data in [0, 1] to uint8 or uint16 by rounding.

    Parameters
    ----------
    image : array_like
        Float in [0, 1] (any shape), or uint8, uint16 or bool data, which are
        first scaled to [0, 1] as everywhere in texsynth.
    bits : {8, 16}
        Depth of the result.

    Returns
    -------
    numpy.ndarray
        uint8 (0-255) or uint16 (0-65535), same shape as ``image``.

    Raises
    ------
    TypeError
        If ``image`` is None, not numeric or of an unsupported dtype (signed
        integers: scale them to [0, 1] first), or ``bits`` is not an integer.
    ValueError
        If ``image`` is empty, holds NaN or infinity, or floats outside
        [0, 1] (values are not clipped silently: clip them yourself with
        ``np.clip(image, 0, 1)`` if the overshoot is expected, or divide
        0-255 data by 255), ``bits`` is not 8 or 16, or the conversion
        cannot fit in the memory available (refused before it starts).

    Examples
    --------
    >>> to_uint(np.array([0.0, 0.5, 1.0]))
    array([  0, 128, 255], dtype=uint8)
    >>> to_uint(np.array([0, 255], dtype=np.uint8), 16)
    array([    0, 65535], dtype=uint16)
    """
    bits = check_bits(bits, allow_none=False)
    arr = as_array(image, "image")
    # held at once: the float copy and the output, or the two float copies of uint8 and uint16's scaling
    copy = 4 if arr.dtype == np.float32 else 8
    scaled = arr.dtype in (np.uint8, np.uint16)
    check_memory(arr.size * (2 * copy if scaled else copy + bits // 8), arr.shape, "image",
                 f"the conversion to {bits} bits")
    if np.issubdtype(arr.dtype, np.floating) and arr.size and np.all(np.isfinite(arr)):
        lo, hi = float(arr.min()), float(arr.max())
        if lo < -1e-6 or hi > 1 + 1e-6:
            hint = "divide 0-255 data by 255" if hi > 1.5 else "clip it first with np.clip(image, 0, 1) if the overshoot is expected"
            raise ValueError(f"image has values in [{lo:.4g}, {hi:.4g}] but to_uint converts [0, 1]; {hint}")
    data = as_float_array(arr, "image")  # always a new array: scaled in place below
    top = 255 if bits == 8 else 65535
    data *= top
    np.round(data, out=data)
    return data.astype(np.uint8 if bits == 8 else np.uint16)


_RANGE_TOLERANCE = 1e-6  # as texsynth.core._validate: a float image may overshoot [0, 1] by this much


def _check_value_range(value_range):
    try:
        lo, hi = (float(v) for v in value_range)
    except (TypeError, ValueError):
        raise TypeError(f"value_range must be a pair of numbers (low, high), got {short.repr(value_range)}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise ValueError(f"value_range must be finite numbers (low, high) with low < high, got {value_range!r}")
    return lo, hi


def _check_image_shape(arr, name):
    """The shape rule of :func:`texsynth.core._validate.as_image`: ``(H, W)`` or ``(H, W, C)``, C in 1..4, not
    empty."""
    if not (arr.ndim == 2 or (arr.ndim == 3 and 1 <= arr.shape[-1] <= 4)):
        raise ValueError(f"{name} must have shape (H, W) or (H, W, C) with C in 1..4, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape}); pass an image with at least one pixel")


def _normalize(data, value_range, name):
    arr = as_array(data, name)
    if not np.issubdtype(arr.dtype, np.floating):  # uint8, uint16, bool: [0, 1] by their white level
        if value_range is not None and _check_value_range(value_range) != (0.0, 1.0):
            raise ValueError(f"{name} is {arr.dtype}, whose range is [0, 1] by its white level; pass value_range=None")
        return as_image(arr, name), (0.0, 1.0)
    _check_image_shape(arr, name)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values; replace them (e.g. np.nan_to_num) first")
    lo, hi = float(arr.min()), float(arr.max())
    if value_range is None:
        if lo >= -_RANGE_TOLERANCE and hi <= 1 + _RANGE_TOLERANCE:
            return as_image(arr, name), (0.0, 1.0)
        value_range = (lo, hi) if hi > lo else (lo, lo + 1.0)  # a constant image: all 0, standing for its value
    low, high = _check_value_range(value_range)
    slack = _RANGE_TOLERANCE * (high - low)
    if lo < low - slack or hi > high + slack:
        raise ValueError(f"{name} has values in [{lo:.6g}, {hi:.6g}], outside value_range=({low:.6g}, {high:.6g}); "
                         "pass a range that holds them, or None for the data's own")
    unit = (arr.astype(np.float64) - low) / (high - low)
    np.clip(unit, 0.0, 1.0, out=unit)
    return unit.astype(np.float32 if arr.dtype == np.float32 else np.float64), (low, high)


def normalize_range(image, value_range=None):
    """Scale float data of any range into [0, 1], and say which range 0 and 1 stand for.

    The library's functions take images in [0, 1] (``docs/conventions.md``);
    heights, displacement and HDR colour are not. This maps them in by one
    affine map for the whole array (all channels together, so colours keep
    their ratios), and :func:`restore_range` maps a result back. Rendering
    through a source-coordinate map (:func:`texsynth.apply_coordinates`)
    commutes with it exactly; a synthesis sees the scaled values (options
    with absolute values, such as error bounds, apply to them).

    Parameters
    ----------
    image : array_like
        ``(H, W)`` or ``(H, W, C)`` float data (any finite values), or uint8,
        uint16 or bool data (scaled by their white level as everywhere).
    value_range : (float, float), optional
        The ``(low, high)`` to map to 0 and 1 (e.g. a range shared by several
        files); None: the data's minimum and maximum, or ``(0.0, 1.0)`` when
        the data already lies in [0, 1] (returned unchanged).

    Returns
    -------
    image : numpy.ndarray
        In [0, 1], float32 for float32 data, else float64.
    value_range : (float, float)
        ``(low, high)``: ``low + image * (high - low)`` is the data.

    Raises
    ------
    TypeError
        For a non-array ``image`` or unsupported dtype, or a ``value_range``
        that is not a pair of numbers.
    ValueError
        For a bad shape, NaN or infinite values, data outside a given
        ``value_range``, or a ``value_range`` with ``low >= high``.

    Examples
    --------
    >>> unit, value_range = normalize_range(np.array([[-0.5, 0.0], [0.5, 1.5]]))
    >>> unit.tolist(), value_range
    ([[0.0, 0.25], [0.5, 1.0]], (-0.5, 1.5))
    >>> restore_range(unit, value_range).tolist()
    [[-0.5, 0.0], [0.5, 1.5]]
    """
    return _normalize(image, None if value_range is None else _check_value_range(value_range), "image")


def restore_range(image, value_range):
    """Map an image in [0, 1] back to the range :func:`normalize_range` (or ``load_image(..., normalize=True)``) gave.

    Parameters
    ----------
    image : array_like
        Float in [0, 1] (or uint8/uint16/bool), any shape.
    value_range : (float, float)
        ``(low, high)``: 0 becomes ``low`` and 1 ``high``.

    Returns
    -------
    numpy.ndarray
        ``low + image * (high - low)``: float32 for float32 ``image``, else
        float64; ``image`` as float, unchanged, for ``(0.0, 1.0)``.

    Raises
    ------
    TypeError, ValueError
        For an ``image`` outside [0, 1] (docs/conventions.md, "Images")
        or a bad ``value_range``.

    Examples
    --------
    >>> restore_range(np.array([0.0, 0.5, 1.0]), (-2.0, 6.0)).tolist()
    [-2.0, 2.0, 6.0]
    """
    low, high = _check_value_range(value_range)
    unit = as_float_array(as_array(image, "image"), "image")
    if (low, high) == (0.0, 1.0):
        return unit
    data = low + unit.astype(np.float64) * (high - low)
    return data.astype(np.float32) if unit.dtype == np.float32 else data


def imwrite(tmp, pixels, **kwargs):
    """``iio.imwrite(tmp, pixels, **kwargs)``, encoded in memory and then written to ``tmp`` by this function.

    Writing to the file through imageio, a failing write (a full disk) is raised, then tried again by
    imageio's writer when it is collected, which prints an "Exception ignored" traceback after the error;
    and Pillow's encoders take a short write for a complete one (a truncated JPEG or BMP that passes for
    written). A file written here raises once, and Python's file object writes all bytes or raises.
    """
    data = iio.imwrite("<bytes>", pixels, **kwargs)
    with open(tmp, "wb") as f:
        f.write(data)


def _save_npy(tmp, data):
    with open(tmp, "wb") as f:  # a file object: np.save would append ".npy" to a name ending in ".NPY"
        np.save(f, data)


# --------------------------------------------------------------------------- #
# saving
# --------------------------------------------------------------------------- #
def check_suffix(path, *, frames=False):
    """The lower-case suffix of ``path`` if :func:`save_image` (or, with ``frames``, :func:`save_frames`)
    writes that format; else a ValueError listing the ones it does. Lets a caller refuse a path before
    a long computation.

    >>> check_suffix("out.PNG"), check_suffix("frames", frames=True)
    ('.png', '')
    """
    suffix = Path(path).suffix.lower()
    if frames and suffix not in {"", ".gif", ".png"} | VIDEO:
        raise ValueError(
            f"path suffix {suffix!r} is not a frame-sequence format; use '.gif', '.png' (animated PNG), a video "
            f"({', '.join(sorted(VIDEO))}) or a path without suffix for a folder of PNG frames"
        )
    if not frames and suffix not in EIGHT_BIT | SIXTEEN_BIT | EXR | {".npy"}:
        raise ValueError(
            f"path suffix {suffix!r} is not a supported image format; use one of "
            f"{sorted(EIGHT_BIT | SIXTEEN_BIT | EXR | {'.npy'})}"
        )
    if suffix in EXR and not frames:
        openexr()  # an ImportError naming the extra, before any work
    return suffix


def save_image(path, image, *, bits=None, overwrite=False):
    """Write an image atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Target file; its suffix chooses the format. ``.npy`` stores the float
        array unchanged (useful for volumes); ``.exr`` (OpenEXR, with the
        ``exr`` extra) stores float samples, named Y, YA, RGB or RGBA.
    image : array_like
        Float in [0, 1] (or uint8/uint16/bool), ``(H, W)`` or ``(H, W, C)``.
        The float formats (TIFF with ``bits=32``, EXR) also store float data
        outside [0, 1] as it is (e.g. :func:`restore_range`'s).
    bits : {None, 8, 16, 32}
        Bits per sample; None means 16 for TIFF, 32 for EXR, 8 for everything
        else. 16 bits need a PNG or a TIFF (grey, grey+alpha, RGB or RGBA),
        or an EXR (half floats); 32 writes float32 samples and needs a TIFF
        or an EXR.
    overwrite : bool
        Replace an existing file. Off by default: nothing is replaced by surprise.

    Returns
    -------
    pathlib.Path
        The written path.

    Raises
    ------
    TypeError
        For a ``path`` that is not a str or os.PathLike, a non-array
        ``image``, a non-bool ``overwrite`` or a non-integer ``bits``.
    ValueError
        For an unsupported suffix, a bad ``image`` (docs/conventions.md,
        "Images"; float data outside [0, 1] for an integer format), or a
        ``bits`` the format cannot store.
    FileExistsError
        If ``path`` exists and ``overwrite`` is False, or is a folder.
    FileNotFoundError
        If the folder of ``path`` does not exist.
    ImportError
        For a ``.exr`` path without the OpenEXR package
        (``python -m pip install '.[exr]'`` in a checkout).

    Notes
    -----
    The file is written under a hidden temporary name beside ``path`` and
    renamed when complete; the temporary file is removed if the write fails or
    the process gets SIGINT or SIGTERM. A new file gets the permissions the
    umask gives (``0644`` for the usual umask ``022``); a replaced file keeps
    its permission bits.

    JPEG, GIF, BMP and PPM/PGM store no alpha channel: the alpha channel of a
    2- or 4-channel image is dropped and the grey or colour channels written.
    TGA (8 bits) keeps it.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     print(save_image(d + "/grey.png", np.zeros((4, 4))).name)
    grey.png
    """
    path = as_path(path)
    overwrite = check_bool(overwrite, "overwrite")
    bits = check_bits(bits, allow_none=True, allowed=(8, 16, 32))
    suffix = path.suffix.lower()
    if suffix == ".npy":
        data = as_float_array(as_array(image, "image"), "image")
        prepare_target(path, overwrite)
        atomic_write(path, lambda tmp: _save_npy(tmp, data))
        return path
    check_suffix(path)
    if bits is None:
        bits = 16 if suffix in SIXTEEN_BIT else 32 if suffix in EXR else 8
    if bits == 8 and suffix in EXR:
        raise ValueError("bits=8 cannot be stored in an .exr file (half or float samples); pass bits=16 (half) or "
                         "32 (float), or save as .png")
    if bits == 16 and suffix not in {".png", ".tif", ".tiff"} | EXR:
        raise ValueError(f"bits=16 needs a .png, .tif or .exr path, got {suffix!r}")
    if bits == 32 and suffix not in SIXTEEN_BIT | EXR:
        raise ValueError(f"bits=32 (float32 samples) needs a .tif or .exr path, got {suffix!r}; pass bits=16 for a "
                         "16-bit PNG, or save as .tif")
    floats = bits == 32 or suffix in EXR
    data = _float_samples(image)
    if not floats and np.issubdtype(data.dtype, np.floating) and (data.min() < 0 or data.max() > 1):
        lo, hi = float(data.min()), float(data.max())
        hint = "; or divide 0-255 data by 255" if hi > 1.5 and lo >= 0 else ""
        raise ValueError(f"image has values in [{lo:.6g}, {hi:.6g}] but a {suffix} file stores [0, 1]; save it as .exr "
                         f"or .tif with bits=32 to keep the values, or scale it in with "
                         f"texsynth.io.normalize_range{hint}")
    if suffix in EXR and bits == 16 and float(np.abs(data).max()) > HALF_MAX:
        raise ValueError(f"image has values up to {float(np.abs(data).max()):.6g} in magnitude, beyond the largest "
                         f"half float ({HALF_MAX:g}); pass bits=32 for float32 samples")
    pixels = data.astype(np.float32) if floats else to_uint(data, bits)
    if pixels.ndim == 3 and pixels.shape[-1] == 1:
        pixels = pixels[..., 0]
    if suffix in NO_ALPHA and pixels.ndim == 3 and pixels.shape[-1] in (2, 4):
        pixels = pixels[..., :-1] if pixels.shape[-1] == 4 else pixels[..., 0]
    prepare_target(path, overwrite)
    if suffix in EXR:
        atomic_write(path, lambda tmp: write_exr(tmp, pixels, bits))
    elif bits == 16 and suffix == ".png" and pixels.ndim == 3:  # imageio's Pillow writer has no 16-bit colour PNG
        atomic_write(path, lambda tmp: write_png16(tmp, pixels))
    else:
        atomic_write(path, lambda tmp: imwrite(tmp, pixels, extension=suffix))
    return path


def _float_samples(image):
    """An image for a float format: uint8/uint16/bool scaled to [0, 1], float data kept as it is (finite)."""
    arr = as_array(image, "image")
    if not np.issubdtype(arr.dtype, np.floating):
        return as_image(arr, "image")
    _check_image_shape(arr, "image")
    if not np.all(np.isfinite(arr)):
        raise ValueError("image contains NaN or infinite values; replace them (e.g. np.nan_to_num) before saving")
    if float(arr.min()) >= -_RANGE_TOLERANCE and float(arr.max()) <= 1 + _RANGE_TOLERANCE:
        return as_image(arr, "image")  # [0, 1] data as before: the tolerance clipped away
    return arr
