"""Loading and saving images, volumes and frame sequences.

Loading converts to float in [0, 1] with the conventions of
:mod:`texsynth.core._validate`: 8- and 16-bit files are divided by their white
level (255, 65535), CMYK files are converted to RGB, and integer pixel types
without an agreed white level (signed, or wider than 16 bits) are refused
rather than guessed.

Saving converts float [0, 1] to the file type's integer format (uint8 for
PNG/JPEG/GIF/BMP, uint16 for 16-bit PNG and TIFF), or writes float32 TIFF
(``bits=32``). 16-bit PNG is read and written for grey, grey+alpha, RGB and
RGBA: Pillow (imageio's PNG plugin) handles 16-bit grey only and reads 16-bit
colour PNG as 8 bits, so those go through a small PNG codec of this module
(zlib and numpy, no new dependency). Every save is atomic
(:mod:`texsynth.core.files`): the data go to a hidden temporary file beside
the target, which is renamed over the target only once complete, so a file is
never half-written. The temporary file
is removed when the write fails or the process is interrupted, by Ctrl-C
(SIGINT) or by SIGTERM (``kill``, ``timeout``, a job scheduler); what a killed
writer (SIGKILL) left is removed by the next write of the same target. New
files get the permissions the umask gives, as any other program's output; a
replaced file keeps its permission bits. Nothing is overwritten unless
``overwrite=True``.
"""

from __future__ import annotations

import importlib.util
import numbers
import re
import reprlib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import struct
import zlib

import imageio.v3 as iio
import numpy as np

from .core._validate import as_array, as_float_array, as_image, check_bool, check_memory, check_positive_float
from .core.files import as_path, atomic_write, prepare_target, swap_folder

__all__ = ["load_image", "save_image", "save_chunked", "load_frames", "save_frames", "to_uint", "image_bits",
           "save_coordinates",
           "load_coordinates"]

_EIGHT_BIT = {".png", ".jpg", ".jpeg", ".gif", ".bmp", ".ppm", ".pgm", ".webp"}
_SIXTEEN_BIT = {".tif", ".tiff"}
# formats that store no alpha channel: an alpha channel is dropped (documented in save_image)
_NO_ALPHA = {".jpg", ".jpeg", ".bmp", ".ppm", ".pgm", ".gif"}
# frame-sequence containers written through imageio-ffmpeg (the ``video`` extra)
# the containers imageio's ffmpeg writer fills with its default codec (H.264 or MPEG-4); .m4v, .mpg and .flv
# go to other imageio plugins, and WebM does not take H.264
_VIDEO = {".mp4", ".mov", ".avi", ".mkv", ".mpeg", ".wmv"}
# a GIF frame delay is a 16-bit count of centiseconds
_GIF_MAX_DELAY_MS = 655_350
# file signatures of formats whose samples are unsigned and at most 16 bits (PNG, Netpbm P1-P7):
# Pillow hands their 16-bit samples over as int32 (16-bit Netpbm scaled to 0..65535)
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_NETPBM_MAGIC = tuple(f"P{k}".encode() for k in range(1, 8))
_TIFF_MAGIC = (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")  # little/big-endian TIFF and BigTIFF

_short = reprlib.Repr()
_short.maxstring = _short.maxother = 60


# --------------------------------------------------------------------------- #
# argument checks
# --------------------------------------------------------------------------- #
def _check_bits(bits, *, allow_none, allowed=(8, 16)):
    if bits is None and allow_none:
        return None
    words = ", ".join(map(str, allowed[:-1])) + f" or {allowed[-1]}"
    choices = f"None, {words}" if allow_none else words
    if not isinstance(bits, numbers.Integral) or isinstance(bits, (bool, np.bool_)):
        raise TypeError(f"bits must be {choices}, got {type(bits).__name__} {_short.repr(bits)}")
    if bits not in allowed:
        raise ValueError(f"bits must be {choices}, got {bits!r}")
    return int(bits)


# --------------------------------------------------------------------------- #
# 16-bit colour PNG (Pillow reads it as 8 bits and cannot write it)
# --------------------------------------------------------------------------- #
_PNG_COLOUR_TYPES = {1: 0, 2: 4, 3: 2, 4: 6}  # channels -> PNG colour type (grey, grey+alpha, RGB, RGBA)
_PNG_CHANNELS = {0: 1, 4: 2, 2: 3, 6: 4}


def _png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def _write_png16(path, pixels):
    """Write uint16 ``(H, W)`` or ``(H, W, C)`` pixels as a 16-bit PNG (filter type 0 on every row)."""
    h, w = pixels.shape[:2]
    channels = 1 if pixels.ndim == 2 else pixels.shape[2]
    rows = np.ascontiguousarray(pixels, dtype=">u2").reshape(h, w * channels).view(np.uint8)
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rows], axis=1)  # a filter byte (0, none) per row
    header = struct.pack(">IIBBBBB", w, h, 16, _PNG_COLOUR_TYPES[channels], 0, 0, 0)
    with open(path, "wb") as f:
        f.write(_PNG_MAGIC + _png_chunk(b"IHDR", header) + _png_chunk(b"IDAT", zlib.compress(raw.tobytes(), 6))
                + _png_chunk(b"IEND", b""))


def _file_head(path, n):
    """The first ``n`` bytes of a file (fewer if it is shorter; none if it cannot be read)."""
    try:
        with open(path, "rb") as f:
            return f.read(n)
    except OSError:
        return b""


def _png_header(path):
    """``(width, height, bit depth, colour type, interlace)`` of a PNG file, or None for another file."""
    head = _file_head(path, 33)
    if not head.startswith(_PNG_MAGIC) or len(head) < 33 or head[12:16] != b"IHDR":
        return None
    w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", head[16:29])
    return w, h, depth, colour, interlace


def _unfilter(data, h, stride, bpp):
    """Undo the PNG row filters (types 0-4) of ``data`` ``(h, 1 + stride)`` bytes: ``(h, stride)`` uint8.

    Filter types None, Sub and Up are undone a row at a time (Sub as a running sum
    per byte lane). Average and Paeth need the decoded pixel to the left, above
    and above-left, so an image that uses them is decoded along anti-diagonals
    of pixels (``r + c = t``): every pixel of one diagonal depends only on
    earlier ones, so each diagonal is one vectorised step (about 1 s for
    2048 x 2048 RGB).
    """
    types, rows = data[:, 0], data[:, 1:].astype(np.int32)
    if np.any(types > 4):
        raise ValueError(f"PNG row filter type {int(types.max())} is not defined (0-4): the file is damaged")
    if np.any(types >= 3):
        return _unfilter_diagonals(rows, types, h, stride // bpp, bpp)
    out = np.zeros((h, stride), np.int32)
    prior = np.zeros(stride, np.int32)
    for r in range(h):
        line, kind = rows[r], types[r]
        if kind == 0:
            cur = line
        elif kind == 2:
            cur = (line + prior) & 0xFF
        else:  # Sub: a running sum per byte lane of a pixel
            cur = (np.cumsum(line.reshape(-1, bpp), axis=0) & 0xFF).reshape(-1)
        out[r] = prior = cur
    return out.astype(np.uint8)


def _unfilter_diagonals(rows, types, h, w, bpp):
    """:func:`_unfilter` for images with Average or Paeth rows, one anti-diagonal of pixels at a time."""
    filtered = rows.reshape(h, w, bpp)
    out = np.zeros((h + 1, w + 1, bpp), np.int32)  # out[r + 1, c + 1] is pixel (r, c); zeros before the image
    kinds = types.astype(np.int32)
    for t in range(h + w - 1):
        r = np.arange(max(0, t - w + 1), min(h, t + 1))
        c = t - r
        left, up, corner = out[r + 1, c], out[r, c + 1], out[r, c]
        kind = kinds[r][:, None]
        p = left + up - corner
        pa, pb, pc = np.abs(p - left), np.abs(p - up), np.abs(p - corner)
        paeth = np.where((pa <= pb) & (pa <= pc), left, np.where(pb <= pc, up, corner))
        pred = np.select([kind == 1, kind == 2, kind == 3, kind == 4], [left, up, (left + up) >> 1, paeth], 0)
        out[r + 1, c + 1] = (filtered[r, c] + pred) & 0xFF
    return out[1:, 1:].reshape(h, w * bpp).astype(np.uint8)


def _read_png16(path, header):
    """Read a non-interlaced 16-bit PNG as uint16 ``(H, W)`` or ``(H, W, C)``."""
    w, h, _, colour, interlace = header
    if interlace:
        raise ValueError(f"{str(path)!r} is an interlaced 16-bit colour PNG, which texsynth does not decode; "
                         "save it without interlacing (or as a 16-bit TIFF)")
    chunks = []
    with open(path, "rb") as f:
        f.read(8)
        while True:
            head = f.read(8)
            if len(head) < 8:
                raise ValueError(f"{str(path)!r} ends before its IEND chunk: the PNG is truncated")
            length, kind = struct.unpack(">I4s", head)
            body = f.read(length)
            f.read(4)
            if kind == b"IDAT":
                chunks.append(body)
            elif kind == b"IEND":
                break
    channels = _PNG_CHANNELS[colour]
    stride = w * channels * 2
    try:
        data = np.frombuffer(zlib.decompress(b"".join(chunks)), np.uint8)
    except zlib.error as exc:
        raise ValueError(f"cannot read {str(path)!r} as a PNG: {exc}") from None
    if data.size != h * (stride + 1):
        raise ValueError(f"{str(path)!r} holds {data.size} bytes of pixels where a {w}x{h} 16-bit PNG with "
                         f"{channels} channels has {h * (stride + 1)}: the file is damaged")
    rows = _unfilter(data.reshape(h, stride + 1), h, stride, channels * 2)
    pixels = rows.view(">u2").astype(np.uint16).reshape(h, w, channels)
    return pixels[..., 0] if channels == 1 else pixels


def image_bits(path):
    """Bits per sample of an image file: 8, 16 or 32 (floating point).

    Parameters
    ----------
    path : str or os.PathLike
        An image file that :func:`load_image` reads.

    Returns
    -------
    int
        16 for 16-bit PNG, PGM/PPM and TIFF files, 32 for floating-point
        TIFF files, 8 for everything else (palette, 1-bit and 8-bit files).

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
    header = _png_header(path)
    if header is not None:
        return 16 if header[2] == 16 else 8
    try:
        kind = iio.improps(path).dtype
    except Exception as exc:
        raise ValueError(f"cannot read {str(path)!r} as an image: {exc}") from None
    if np.issubdtype(kind, np.floating):
        return 32
    if kind == np.uint16 or (kind == np.int32 and _holds_at_most_16_bits(path)):  # Pillow: 16-bit PGM as int32
        return 16
    return 8


# --------------------------------------------------------------------------- #
# loading
# --------------------------------------------------------------------------- #
def _read(path, what="an image", **kwargs):
    try:
        return iio.imread(path, **kwargs)
    except Exception as exc:  # imageio raises many types; one clear message
        raise ValueError(f"cannot read {str(path)!r} as {what}: {exc}") from None


def _is_cmyk(path):
    """Whether Pillow opens ``path`` as a CMYK image (JPEG and TIFF from print workflows)."""
    try:
        return iio.immeta(path, plugin="pillow").get("mode") == "CMYK"
    except Exception:  # not a format Pillow reads: then imageio's reader is the only one
        return False


def _check_tiff_size(path):
    """Refuse a TIFF whose header claims an image larger than Pillow's decompression-bomb limit.

    Pillow refuses such PNG and JPEG files before decoding them; tifffile, imageio's TIFF reader,
    allocates whatever the header claims, so the claim is checked here from the header, before any
    pixel is read.
    """
    import tifffile
    from PIL import Image

    if Image.MAX_IMAGE_PIXELS is None:  # the user lifted the limit
        return
    limit = 2 * Image.MAX_IMAGE_PIXELS  # Pillow warns above MAX_IMAGE_PIXELS and refuses above twice that
    try:
        with tifffile.TiffFile(path) as tif:
            series = tif.series[0]
            dims = dict(zip(series.axes, series.shape))
    except Exception:  # a damaged file: imageio's reader gives the error
        return
    width, height, depth = dims.get("X", 1), dims.get("Y", 1), dims.get("Z", 1)
    if width * height * depth > limit:
        size = f"{width} x {height}" + (f" x {depth}" if depth > 1 else "")
        raise ValueError(
            f"{str(path)!r} is a TIFF image of {size} pixels ({width * height * depth:,}), more than the limit of "
            f"{limit:,} pixels that load_image reads (Pillow's limit against decompression bombs, which PNG and "
            "JPEG files get too); read a part of it with tifffile (tifffile.imread(path, aszarr=True)), or, "
            "if you trust the file, raise the limit with PIL.Image.MAX_IMAGE_PIXELS"
        )


def _holds_at_most_16_bits(path):
    """Whether the file is a PNG or Netpbm file: unsigned samples of at most 16 bits, by the format."""
    head = _file_head(path, 8)
    return head.startswith(_PNG_MAGIC) or head[:2] in _NETPBM_MAGIC


def _supported_integers(data, path):
    """uint8/uint16 as is; the int32 Pillow gives for 16-bit PNG/Netpbm as uint16; refuse other integers."""
    kind = data.dtype
    if not np.issubdtype(kind, np.integer) or kind in (np.uint8, np.uint16):
        return data
    lo, hi = (int(data.min()), int(data.max())) if data.size else (0, 0)
    if kind == np.int32 and _holds_at_most_16_bits(path) and 0 <= lo and hi <= 65535:
        return data.astype(np.uint16)
    raise ValueError(
        f"path {str(path)!r} holds {kind} pixels (values {lo}..{hi}): signed and wider-than-16-bit integers have "
        "no agreed white level, so texsynth does not guess one. Convert the file to 8- or 16-bit unsigned "
        "(or float in [0, 1]), or read it yourself (imageio.v3.imread) and divide it by its white level "
        "(e.g. 4095 for 12-bit sensor data) before passing the array"
    )


def load_image(path):
    """Read an image file as float in [0, 1].

    Parameters
    ----------
    path : str or os.PathLike
        Any format imageio reads (PNG, JPEG, PGM/PPM, TIFF, BMP, ...).

    Returns
    -------
    numpy.ndarray
        ``(H, W)`` for grey files, ``(H, W, C)`` otherwise (alpha kept as the
        last channel), float64 in [0, 1] (float32 for float32 TIFFs).

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike.
    FileNotFoundError
        If ``path`` does not exist or is a folder.
    ValueError
        If the file cannot be read as an image, holds several frames, holds
        pixels of an integer type without an agreed white level, or claims
        more pixels than Pillow's limit against decompression bombs
        (``2 * PIL.Image.MAX_IMAGE_PIXELS``, checked from the header for
        TIFF files as Pillow does for PNG and JPEG).

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
    """
    path = as_path(path)
    if path.is_dir():
        raise FileNotFoundError(f"path {str(path)!r} is a folder, not an image file; load_frames reads a folder of frames")
    if not path.is_file():
        raise FileNotFoundError(f"path {str(path)!r} does not exist or is not a file")
    header = _png_header(path)
    if _file_head(path, 4) in _TIFF_MAGIC:
        _check_tiff_size(path)
    if header is not None and header[2] == 16 and header[3] in (2, 4, 6):  # 16-bit colour: Pillow reads 8 bits
        data = _read_png16(path, header)
    else:
        data = _read(path)
    if data.ndim == 3 and data.shape[-1] == 4 and _is_cmyk(path):
        data = _read(path, plugin="pillow", mode="RGB")
    if (data.ndim == 3 and data.shape[-1] > 4 and data.shape[0] > 1) or (data.ndim == 4 and data.shape[0] > 1):
        raise ValueError(f"{str(path)!r} holds {data.shape[0]} frames; use load_frames for animations")
    if data.ndim == 4 and data.shape[0] == 1:
        data = data[0]
    data = _supported_integers(data, path)
    return as_image(data, name=f"image in {path.name}")


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
    bits = _check_bits(bits, allow_none=False)
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


def _imwrite(tmp, pixels, **kwargs):
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
    if frames and suffix not in {"", ".gif", ".png"} | _VIDEO:
        raise ValueError(
            f"path suffix {suffix!r} is not a frame-sequence format; use '.gif', '.png' (animated PNG), a video "
            f"({', '.join(sorted(_VIDEO))}) or a path without suffix for a folder of PNG frames"
        )
    if not frames and suffix not in _EIGHT_BIT | _SIXTEEN_BIT | {".npy"}:
        raise ValueError(
            f"path suffix {suffix!r} is not a supported image format; use one of "
            f"{sorted(_EIGHT_BIT | _SIXTEEN_BIT | {'.npy'})}"
        )
    return suffix


def save_image(path, image, *, bits=None, overwrite=False):
    """Write an image atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Target file; its suffix chooses the format. ``.npy`` stores the float
        array unchanged (useful for volumes).
    image : array_like
        Float in [0, 1] (or uint8/uint16/bool), ``(H, W)`` or ``(H, W, C)``.
    bits : {None, 8, 16, 32}
        Bits per sample; None means 16 for TIFF, 8 for everything else. 16
        bits need a PNG or a TIFF (grey, grey+alpha, RGB or RGBA); 32 writes
        float32 samples in [0, 1] and needs a TIFF.
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
        For an unsupported suffix, a bad ``image`` (see
        :mod:`texsynth.core._validate`), or a ``bits`` the format cannot store.
    FileExistsError
        If ``path`` exists and ``overwrite`` is False, or is a folder.
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Notes
    -----
    The file is written under a hidden temporary name beside ``path`` and
    renamed when complete; the temporary file is removed if the write fails or
    the process gets SIGINT or SIGTERM. A new file gets the permissions the
    umask gives (``0644`` for the usual umask ``022``); a replaced file keeps
    its permission bits.

    JPEG, GIF, BMP and PPM/PGM store no alpha channel: the alpha channel of a
    2- or 4-channel image is dropped and the grey or colour channels written.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     print(save_image(d + "/grey.png", np.zeros((4, 4))).name)
    grey.png
    """
    path = as_path(path)
    overwrite = check_bool(overwrite, "overwrite")
    bits = _check_bits(bits, allow_none=True, allowed=(8, 16, 32))
    suffix = path.suffix.lower()
    if suffix == ".npy":
        data = as_float_array(as_array(image, "image"), "image")
        prepare_target(path, overwrite)
        atomic_write(path, lambda tmp: _save_npy(tmp, data))
        return path
    check_suffix(path)
    data = as_image(as_array(image, "image"), "image")
    if bits is None:
        bits = 16 if suffix in _SIXTEEN_BIT else 8
    if bits == 16 and suffix not in {".png", ".tif", ".tiff"}:
        raise ValueError(f"bits=16 needs a .png or .tif path, got {suffix!r}")
    if bits == 32 and suffix not in _SIXTEEN_BIT:
        raise ValueError(f"bits=32 (float32 samples) needs a .tif path, got {suffix!r}; pass bits=16 for a 16-bit "
                         "PNG, or save as .tif")
    pixels = data.astype(np.float32) if bits == 32 else to_uint(data, bits)
    if pixels.ndim == 3 and pixels.shape[-1] == 1:
        pixels = pixels[..., 0]
    if suffix in _NO_ALPHA and pixels.ndim == 3 and pixels.shape[-1] in (2, 4):
        pixels = pixels[..., :-1] if pixels.shape[-1] == 4 else pixels[..., 0]
    prepare_target(path, overwrite)
    if bits == 16 and suffix == ".png" and pixels.ndim == 3:  # imageio's Pillow writer has no 16-bit colour PNG
        atomic_write(path, lambda tmp: _write_png16(tmp, pixels))
    else:
        atomic_write(path, lambda tmp: _imwrite(tmp, pixels, extension=suffix))
    return path


def load_frames(path):
    """Read a frame sequence as ``(T, H, W, C)`` float in [0, 1].

    Parameters
    ----------
    path : str or os.PathLike
        An animated GIF, a folder of still images (read in sorted name order),
        or a video file (``.mp4``, ``.avi``, ...; needs the ``video`` extra,
        imageio-ffmpeg).

    Returns
    -------
    numpy.ndarray
        ``(T, H, W, C)``; grey frames get ``C == 1`` (also from a GIF or video,
        whose frames are stored as RGB: equal channels are read as grey).

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike.
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file cannot be read as frames, a folder holds no images or
        images of different shapes, or the pixels are of an integer type
        without an agreed white level (see :func:`load_image`).
    """
    path = as_path(path)
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.suffix.lower() in _EIGHT_BIT | _SIXTEEN_BIT)
        if not files:
            raise ValueError(f"folder {str(path)!r} contains no image files")
        frames = [load_image(p) for p in files]
        shapes = {f.shape for f in frames}
        if len(shapes) != 1:
            raise ValueError(f"frames in {str(path)!r} have different shapes {sorted(shapes)}")
        data = np.stack(frames)
    elif path.is_file():
        is_gif = path.suffix.lower() == ".gif"
        hint = "" if is_gif else " (videos need: pip install 'texsynth[video]')"
        try:
            raw = iio.imread(path, index=None)
        except Exception as exc:
            if not is_gif:
                raise ValueError(f"cannot read {str(path)!r} as frames: {exc}{hint}") from None
            # a GIF with transparency decodes to RGB and RGBA frames: read all as RGBA
            raw = _read(path, "frames", index=None, mode="RGBA")
            if np.all(raw[..., 3] == 255):
                raw = raw[..., :3]
        if raw.ndim == 2 or (raw.ndim == 3 and not is_gif and raw.shape[-1] <= 4):
            raw = raw[None]
        if raw.ndim == 4 and raw.shape[-1] == 3 and _is_grey(raw):
            raw = raw[..., :1]  # GIF stores grey frames as palette RGB: give back C == 1
        raw = _supported_integers(raw, path)
        data = as_float_array(raw, f"frames in {path.name}")
    else:
        raise FileNotFoundError(f"path {str(path)!r} does not exist")
    if data.ndim == 3:
        data = data[..., None]
    return data


def _is_grey(rgb):
    return bool(np.array_equal(rgb[..., 0], rgb[..., 1]) and np.array_equal(rgb[..., 0], rgb[..., 2]))


def save_frames(path, frames, *, fps=10.0, loop=True, overwrite=False):
    """Write a frame sequence atomically.

    Parameters
    ----------
    path : str or os.PathLike
        ``.gif`` for an animated GIF, ``.png`` for an animated PNG, ``.mp4``
        (or another video container: ``.avi``, ``.mov``, ``.mkv``, ...; needs
        the ``video`` extra), or a path without suffix for a folder of PNG
        frames ``frame_0000.png``...
    frames : array_like
        ``(T, H, W)`` or ``(T, H, W, C)`` in [0, 1].
    fps : float
        Frames per second, finite and > 0 (a GIF needs at least 1/655.35,
        its longest frame delay being 655.35 s).
    loop : bool
        GIF only: loop forever.
    overwrite : bool
        Replace an existing file, or a folder that holds nothing but the
        ``frame_NNNN.png`` files of an earlier save (a folder with other files
        is refused, so a user's files are never deleted).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    TypeError
        For a ``path`` that is not a str or os.PathLike, non-array
        ``frames``, a non-number ``fps`` or a non-bool ``loop`` or
        ``overwrite``.
    ValueError
        For bad ``frames``, an ``fps`` that is not finite and > 0, an
        unsupported suffix, or a video without the ``video`` extra.
    FileExistsError
        If ``path`` exists and ``overwrite`` is False (or is a folder with
        other files).
    OSError
        If the write fails (a full disk); for a video, also if ffmpeg stops
        before writing every frame.

    Notes
    -----
    Like :func:`save_image`, the sequence is written under a hidden temporary
    name (a folder for PNG frames) and renamed when complete; nothing is left
    behind on failure, SIGINT or SIGTERM. New files and folders get the
    permissions the umask gives; a replaced file or frame folder keeps its
    mode. GIF and video store no alpha channel: it is dropped. A video is read
    back once written and its frames counted, as imageio-ffmpeg does not
    report a failed ffmpeg (this adds about a sixth to the time of a write).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = save_frames(d + "/seq", np.zeros((3, 4, 4)))
    ...     print(sorted(p.name for p in path.iterdir()))
    ['frame_0000.png', 'frame_0001.png', 'frame_0002.png']
    """
    path = as_path(path)
    fps = check_positive_float(fps, "fps")
    loop = check_bool(loop, "loop")
    overwrite = check_bool(overwrite, "overwrite")
    suffix = check_suffix(path, frames=True)
    data = as_image(as_array(frames, "frames"), "frames", spatial_dims=3)
    pixels = to_uint(data, 8)
    if pixels.ndim == 4 and pixels.shape[-1] == 1:
        pixels = pixels[..., 0]
    if suffix == "":
        prepare_target(path, overwrite, folder=True)
        _write_frame_folder(path, pixels)
        return path
    if suffix == ".png":  # animated PNG, through Pillow: alpha kept, no extra needed
        prepare_target(path, overwrite)
        atomic_write(path, lambda tmp: _imwrite(tmp, pixels, extension=".png",
                                                duration=1000.0 / fps, loop=0 if loop else 1))
        return path
    if pixels.ndim == 4 and pixels.shape[-1] in (2, 4):  # GIF and video store no alpha
        pixels = pixels[..., :-1] if pixels.shape[-1] == 4 else pixels[..., 0]
    if suffix == ".gif":
        duration = 1000.0 / fps
        if duration > _GIF_MAX_DELAY_MS:
            raise ValueError(
                f"fps={fps:g} is too slow for a GIF, whose longest frame delay is 655.35 s; "
                f"pass fps >= {1000.0 / _GIF_MAX_DELAY_MS:.5f} or save a folder of PNG frames"
            )
        prepare_target(path, overwrite)
        atomic_write(path, lambda tmp: _imwrite(tmp, pixels, extension=".gif",
                                                duration=duration, loop=0 if loop else 1))
        return path
    if importlib.util.find_spec("imageio_ffmpeg") is None:
        raise ValueError(
            f"path {str(path)!r}: writing {suffix!r} videos needs the video extra "
            "(pip install 'texsynth[video]'); or save as .gif or a folder of PNG frames"
        )
    prepare_target(path, overwrite)
    try:
        atomic_write(path, lambda tmp: _write_video(tmp, pixels, suffix, fps, path))
    except OSError:
        raise  # the write failed (a full disk): as for images
    except Exception as exc:
        raise ValueError(f"cannot write {str(path)!r} as a video: {exc}") from None
    return path


def _write_video(tmp, pixels, suffix, fps, path):
    """Encode ``pixels`` into ``tmp`` (for ``path``) with ffmpeg; an OSError if the file does not hold every frame.

    imageio-ffmpeg ignores ffmpeg's exit status, so a write that failed (a full disk) leaves a cut-off
    video and raises nothing: the file is read back and its frames counted.
    """
    import imageio_ffmpeg

    try:
        iio.imwrite(tmp, pixels, extension=suffix, fps=fps)
    except OSError:  # ffmpeg ended while it was still sent frames (a broken pipe)
        written = None
    else:
        try:
            written = imageio_ffmpeg.count_frames_and_secs(tmp)[0]
        except RuntimeError:  # ffmpeg cannot open the file (an MP4 cut off before its index)
            written = 0
    if written != len(pixels):
        raise OSError(f"cannot write {str(path)!r}: ffmpeg stopped before writing its {len(pixels)} frames (a full "
                      "disk? its messages above, if any, say why); nothing was saved")


_FRAME_NAME = re.compile(r"frame_\d{4,}\.png")


def _write_frame_folder(path, pixels):
    """Write ``frame_0000.png``... into a new folder, then swap it in for ``path``.

    An existing folder is replaced only if it holds nothing but frames that
    :func:`save_frames` wrote, so a user's other files are never deleted. The
    new folder gets the permissions the umask gives, or the mode of the
    folder it replaces.
    """
    if path.exists():
        if not path.is_dir():
            raise FileExistsError(f"{str(path)!r} is a file; a frame sequence without suffix is a folder")
        foreign = [p.name for p in path.iterdir() if not _FRAME_NAME.fullmatch(p.name)]
        if foreign:
            raise FileExistsError(
                f"folder {str(path)!r} holds files save_frames did not write ({', '.join(sorted(foreign)[:3])}"
                f"{', ...' if len(foreign) > 3 else ''}); choose another folder"
            )

    def write(tmp):
        for t, frame in enumerate(pixels):
            _imwrite(tmp / f"frame_{t:04d}.png", frame, extension=".png")

    swap_folder(path, write)


# --------------------------------------------------------------------------- #
# images larger than memory
# --------------------------------------------------------------------------- #
_CHUNKED = {".zarr", ".tif", ".tiff"}


def _tile_side(side):
    """A TIFF tile side: a multiple of 16 at most ``side`` (16 at least)."""
    return max(16, side - side % 16)


def _quantize(block, bits):
    """One block as stored: uint8/uint16 by rounding, or float32 for ``bits=32``."""
    return block.astype(np.float32) if bits == 32 else to_uint(block, bits)


def save_chunked(path, image, *, bits=None, overwrite=False, progress=False):
    """Write an image larger than memory block by block: a Zarr store or a tiled BigTIFF.

    Parameters
    ----------
    path : str or os.PathLike
        ``.zarr`` (a Zarr version 3 store: a folder, blocks compressed with
        Zstandard) or ``.tif``/``.tiff`` (a tiled BigTIFF, Deflate-compressed,
        that GDAL, QGIS, libvips and tifffile read tile by tile).
    image : dask.array.Array or array_like
        Float in [0, 1] (or uint8/uint16), ``(H, W)`` or ``(H, W, C)`` with
        ``C`` in 1..4: the lazy result of a method's ``chunks=`` option (e.g.
        :func:`texsynth.patchwork`), or any array (cut into blocks of 1024).
    bits : {None, 8, 16, 32}
        Bits per sample; None means 8 for Zarr and 16 for TIFF (as
        :func:`save_image`); 32 stores float32.
    overwrite : bool
        Replace an existing store or file.
    progress : bool or callable
        Report progress per row of blocks (True: tqdm bar; a callable receives
        ``(step, total, info)``).

    Returns
    -------
    pathlib.Path
        The written path.

    Raises
    ------
    ValueError
        For another suffix, an image that is not ``(H, W[, C])``, values
        outside [0, 1] (found in the block that holds them; nothing is left
        behind), or a ``bits`` outside 8, 16, 32.
    FileExistsError
        If ``path`` exists and ``overwrite`` is False.
    ImportError
        Without Dask, or without Zarr for a ``.zarr`` path
        (``pip install 'texsynth[dask]'`` installs both).

    Notes
    -----
    The image is computed one row of blocks at a time (the blocks of a row in
    parallel on Dask's scheduler: threads by default, or the cluster of an
    active ``dask.distributed.Client``), each block converted to ``bits`` and
    written before the next row starts, so memory holds one row of blocks.
    The store or file is written under a hidden temporary name beside
    ``path`` and renamed when complete, as :func:`save_image` does. A TIFF
    tile is the block rounded down to a multiple of 16 pixels (the format's
    rule; the array is re-chunked to it if needed).

    Examples
    --------
    >>> import tempfile
    >>> from texsynth.procedural import turbulence
    >>> with tempfile.TemporaryDirectory() as d:
    ...     print(save_chunked(d + "/t.zarr", turbulence((300, 200), chunks=128, rng=0) / 2).name)
    t.zarr
    """
    from .core.chunked import require_dask

    path = as_path(path)
    overwrite = check_bool(overwrite, "overwrite")
    bits = _check_bits(bits, allow_none=True, allowed=(8, 16, 32))
    suffix = path.suffix.lower()
    if suffix not in _CHUNKED:
        raise ValueError(f"path suffix {suffix!r} is not a format written block by block; use '.zarr' or '.tif'")
    if bits is None:
        bits = 8 if suffix == ".zarr" else 16
    da = require_dask("save_chunked")
    if not isinstance(image, da.Array):
        image = da.from_array(as_array(image, "image"), chunks=(1024, 1024) + (-1,) * (np.ndim(image) - 2))
    if image.ndim not in (2, 3) or (image.ndim == 3 and not 1 <= image.shape[-1] <= 4) or 0 in image.shape:
        raise ValueError(f"image must be (H, W) or (H, W, C) with C in 1..4, got shape {image.shape}")
    if image.ndim == 3 and image.chunks[2] != (image.shape[2],):
        image = image.rechunk({2: -1})
    if suffix != ".zarr":
        tile = (_tile_side(image.chunks[0][0]), _tile_side(image.chunks[1][0]))
        if tile != (image.chunks[0][0], image.chunks[1][0]):
            image = image.rechunk(tile + image.chunks[2:])
    stored = image.map_blocks(_quantize, bits, dtype=np.float32 if bits == 32 else f"uint{bits}")
    prepare_target(path, overwrite, folder=suffix == ".zarr")
    if suffix == ".zarr":
        try:
            import zarr
        except ImportError:  # pragma: no cover - zarr is in the dask extra
            raise ImportError("writing .zarr needs Zarr: pip install 'texsynth[dask]'") from None
        swap_folder(path, lambda tmp: _write_zarr(zarr, tmp, stored, progress))
    else:
        atomic_write(path, lambda tmp: _write_tiff(tmp, stored, progress))
    return path


def _block_rows(stored, progress):
    """Yield ``(row start, blocks)`` per row of blocks, each row computed at once (its blocks in parallel)."""
    import dask

    from .core._progress import Progress

    r0 = 0
    with Progress(progress, len(stored.chunks[0]), "writing") as bar:
        for i, rows in enumerate(stored.chunks[0]):
            yield r0, dask.compute(*[stored.blocks[i, j] for j in range(len(stored.chunks[1]))])
            r0 += rows
            bar.advance()


def _write_zarr(zarr, folder, stored, progress):
    # Zarr writes on threads of its own, which go on writing when an exception (SIGTERM, Ctrl-C) ends the main
    # thread's wait for them: a block landing after the clean-up would leave a partial store. So every Zarr
    # call runs on a thread of ours, which leaving the ``with`` waits for, before the store is removed.
    with ThreadPoolExecutor(1) as writer:
        array = writer.submit(zarr.create_array, store=str(folder), shape=stored.shape, dtype=stored.dtype,
                              chunks=tuple(c[0] for c in stored.chunks), zarr_format=3, overwrite=True).result()
        for r0, blocks in _block_rows(stored, progress):
            c0 = 0
            for block in blocks:
                region = (slice(r0, r0 + block.shape[0]), slice(c0, c0 + block.shape[1]))
                writer.submit(array.__setitem__, region, block).result()
                c0 += block.shape[1]


def _write_tiff(tmp, stored, progress):
    import tifffile

    th, tw = stored.chunks[0][0], stored.chunks[1][0]

    def tiles():  # row by row, each tile padded to the whole tile size at the right and bottom edges
        for _, blocks in _block_rows(stored, progress):
            for block in blocks:
                pad = [(0, th - block.shape[0]), (0, tw - block.shape[1])] + [(0, 0)] * (block.ndim - 2)
                yield np.pad(block, pad) if any(p[1] for p in pad) else block

    channels = 1 if stored.ndim == 2 else stored.shape[2]
    tifffile.imwrite(tmp, tiles(), shape=stored.shape, dtype=stored.dtype, tile=(th, tw), bigtiff=True,
                     photometric="rgb" if channels >= 3 else "minisblack", compression="zlib",
                     extrasamples=("unassalpha",) if channels in (2, 4) else None)


# --------------------------------------------------------------------------- #
# source-coordinate maps
# --------------------------------------------------------------------------- #
_MAP_ARRAYS = ("coordinates", "weights", "source_index")


def save_coordinates(path, coordinates, weights=None, *, source_index=None, overwrite=False):
    """Write a source-coordinate map atomically as a ``.npz`` file, to re-render channels later.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file.
    coordinates : array_like or info
        The map (``docs/conventions.md``), or an info of a synthesis, whose
        ``coordinates``, ``weights`` and ``source_index`` are saved; a video
        map of :func:`texsynth.patchwork_video` (``(N, H, W, K, 2)``) too.
    weights, source_index : array_like, optional
        As in :func:`texsynth.apply_coordinates` (taken from the info when
        ``coordinates`` is one).
    overwrite : bool
        Replace an existing file.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    ValueError, TypeError
        For a map :func:`texsynth.apply_coordinates` would refuse, a suffix
        other than ``.npz``, or an existing file without ``overwrite``.

    Examples
    --------
    >>> import tempfile, texsynth
    >>> from texsynth import data
    >>> out, info = texsynth.quilt(data.load("bread")[:48, :48], 64, block=16, rng=0, return_info=True)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     saved = load_coordinates(save_coordinates(d + "/map.npz", info))
    >>> bool(np.array_equal(texsynth.apply_coordinates(data.load("bread")[:48, :48], saved), out))
    True
    """
    from .core.coordinates import check_map, check_sources, video_map

    path = as_path(path)
    if path.suffix.lower() != ".npz":
        raise ValueError(f"a source-coordinate map is saved as .npz, got {str(path)!r}; pass a path ending in .npz")
    if hasattr(coordinates, "coordinates"):  # an info of a synthesis
        info = coordinates
        weights = getattr(info, "weights", None) if weights is None else weights
        source_index = getattr(info, "source_index", None) if source_index is None else source_index
        coordinates = info.coordinates
        if coordinates is None:
            raise ValueError(f"this {type(info).__name__} has no coordinates; see its docstring for the options "
                             "that record them")
    if np.ndim(coordinates) == 5:  # a video map (patchwork_video): checked as the one tall map it renders as
        coords, w, sources, _ = video_map(coordinates, weights, source_index)
        coords, w = check_map(coords, w)
        check_sources(sources, coords)
    else:
        coords, w = check_map(coordinates, weights)
        check_sources(source_index, coords)
    arrays = {"coordinates": as_array(coordinates, "coordinates")}
    if w is not None:
        arrays["weights"] = as_array(weights, "weights")
    if source_index is not None:
        arrays["source_index"] = as_array(source_index, "source_index")
    check_bool(overwrite, "overwrite")
    prepare_target(path, overwrite)

    def write(tmp):
        with open(tmp, "wb") as f:  # a file object: np.savez would append ".npz" to another name
            np.savez_compressed(f, **arrays)

    atomic_write(path, write)
    return path


def load_coordinates(path):
    """Read a map written by :func:`save_coordinates`.

    Returns
    -------
    types.SimpleNamespace
        ``coordinates``, ``weights`` and ``source_index`` (the last two None
        when not saved): pass it to :func:`texsynth.apply_coordinates` as
        the map.

    Raises
    ------
    ValueError
        If the file is not a map (missing ``coordinates``, other arrays).
    """
    from types import SimpleNamespace

    path = as_path(path)
    with np.load(path, allow_pickle=False) as data:
        unknown = sorted(set(data.files) - set(_MAP_ARRAYS))
        if "coordinates" not in data.files or unknown:
            raise ValueError(f"{str(path)!r} is not a source-coordinate map (it holds {sorted(data.files)}); pass a "
                             "file written by texsynth.io.save_coordinates or texsynth ... --coordinates")
        return SimpleNamespace(**{name: (data[name] if name in data.files else None) for name in _MAP_ARRAYS})
