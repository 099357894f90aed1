"""Loading and saving images, volumes and frame sequences.

Loading converts to float in [0, 1] with the library's conventions
(docs/conventions.md, "Images"): 8- and 16-bit files are divided by their white
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

OpenEXR files (``.exr``: half or float32 samples) are read and written through
the ``OpenEXR`` package of the Academy Software Foundation, an optional extra
(``pip install 'texsynth[exr]'``); without it a ``.exr`` path raises an
ImportError naming the extra. TGA files (``.tga``, 8 bits, alpha kept) go
through Pillow like PNG.

Float data outside [0, 1] (heights, displacement, HDR colour) is refused by
the library's functions, whose contract is images in [0, 1]; to work on such a
file, ``load_image(path, normalize=True)`` returns the image scaled into
[0, 1] by the file's minimum and maximum together with that ``value_range``,
and :func:`restore_range` maps a result back (the command line does both).
The float formats (float TIFF, EXR) store any finite values.
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
           "normalize_range", "restore_range", "save_coordinates", "load_coordinates"]

_EIGHT_BIT = {".png", ".jpg", ".jpeg", ".gif", ".bmp", ".ppm", ".pgm", ".webp", ".tga"}
_SIXTEEN_BIT = {".tif", ".tiff"}
_EXR = {".exr"}  # half (bits=16) or float32 (bits=32) samples, through the OpenEXR package (the exr extra)
_EXR_MAGIC = b"\x76\x2f\x31\x01"
_HALF_MAX = 65504.0  # the largest finite half-float
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


def _write_png16(path, pixels, text=None):
    """Write uint16 ``(H, W)`` or ``(H, W, C)`` pixels as a 16-bit PNG (filter type 0 on every row), with
    ``text`` (``{keyword: Latin-1 text}``) in tEXt chunks."""
    h, w = pixels.shape[:2]
    channels = 1 if pixels.ndim == 2 else pixels.shape[2]
    rows = np.ascontiguousarray(pixels, dtype=">u2").reshape(h, w * channels).view(np.uint8)
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rows], axis=1)  # a filter byte (0, none) per row
    header = struct.pack(">IIBBBBB", w, h, 16, _PNG_COLOUR_TYPES[channels], 0, 0, 0)
    notes = b"".join(_png_chunk(b"tEXt", key.encode("latin-1") + b"\0" + value.encode("latin-1"))
                     for key, value in (text or {}).items())
    with open(path, "wb") as f:
        f.write(_PNG_MAGIC + _png_chunk(b"IHDR", header) + notes
                + _png_chunk(b"IDAT", zlib.compress(raw.tobytes(), 6)) + _png_chunk(b"IEND", b""))


def _png_text(path):
    """The tEXt chunks of a PNG file before its pixels, ``{keyword: text}``."""
    found = {}
    with open(path, "rb") as f:
        if f.read(8) != _PNG_MAGIC:
            return found
        while True:
            head = f.read(8)
            if len(head) < 8:
                return found
            length, kind = struct.unpack(">I4s", head)
            if kind in (b"IDAT", b"IEND"):
                return found
            body = f.read(length)
            f.read(4)
            if kind == b"tEXt" and b"\0" in body:
                key, value = body.split(b"\0", 1)
                found[key.decode("latin-1")] = value.decode("latin-1")


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


# --------------------------------------------------------------------------- #
# OpenEXR (the exr extra: the OpenEXR package of the Academy Software Foundation)
# --------------------------------------------------------------------------- #
_EXR_CHANNELS = {1: ("Y",), 2: ("Y", "A"), 3: ("R", "G", "B"), 4: ("R", "G", "B", "A")}


def _openexr():
    """The ``OpenEXR`` module, or an ImportError naming the extra that installs it."""
    try:
        import OpenEXR
    except ImportError:
        raise ImportError("reading and writing .exr files needs the OpenEXR package: pip install 'texsynth[exr]' "
                          "(or pip install OpenEXR); or use a float TIFF (.tif, bits=32)") from None
    return OpenEXR


def _has_openexr():
    return importlib.util.find_spec("OpenEXR") is not None


def _open_exr(path, header_only=False):
    OpenEXR = _openexr()
    try:
        return OpenEXR.File(str(path), separate_channels=True, header_only=header_only)
    except Exception as exc:  # OpenEXR raises RuntimeError for a damaged or foreign file
        raise ValueError(f"cannot read {str(path)!r} as an OpenEXR image: {exc}") from None


def _exr_layout(path, names):
    """The channel names :func:`load_image` reads from an EXR file holding ``names``, in order."""
    present = set(names)
    if {"R", "G", "B"} <= present:
        return ["R", "G", "B"] + (["A"] if "A" in present else [])
    if "Y" in present:
        return ["Y"] + (["A"] if "A" in present else [])
    if len(names) == 1:
        return list(names)
    raise ValueError(f"{str(path)!r} holds the EXR channels {sorted(names)}; load_image reads R, G, B (and A), "
                     "Y (and A) or a single channel: read the others with OpenEXR.File(path).channels()")


def _read_exr(path):
    """An EXR file's first part as float32 ``(H, W)`` or ``(H, W, C)`` (half samples widened to float32)."""
    f = _open_exr(path)
    channels = f.channels()
    planes = []
    for name in _exr_layout(path, list(channels)):
        pixels = np.asarray(channels[name].pixels)
        if not np.issubdtype(pixels.dtype, np.floating):
            raise ValueError(f"{str(path)!r}: EXR channel {name!r} holds {pixels.dtype} samples, which have no agreed "
                             "white level; load_image reads half and float channels")
        planes.append(pixels.astype(np.float32))
    if len({p.shape for p in planes}) > 1:
        raise ValueError(f"{str(path)!r} has subsampled EXR channels ({[p.shape for p in planes]}); load_image reads "
                         "channels of the full resolution")
    return planes[0] if len(planes) == 1 else np.stack(planes, axis=-1)


def _exr_bits(path):
    """16 for an EXR file whose channels are all half floats, else 32."""
    channels = _open_exr(path).channels()
    names = _exr_layout(path, list(channels))
    return 16 if all(np.asarray(channels[n].pixels).dtype == np.float16 for n in names) else 32


def _write_exr(tmp, samples, bits, attributes=None):
    """Write float samples ``(H, W[, C])`` as a ZIP-compressed scanline EXR (half for ``bits=16``)."""
    OpenEXR = _openexr()
    planes = samples[..., None] if samples.ndim == 2 else samples
    kind = np.float16 if bits == 16 else np.float32
    channels = {name: np.ascontiguousarray(planes[..., k], dtype=kind)
                for k, name in enumerate(_EXR_CHANNELS[planes.shape[-1]])}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, **(attributes or {})}
    try:
        OpenEXR.File(header, channels).write(str(tmp))
    except RuntimeError as exc:  # OpenEXR's write errors (a full disk, a read-only folder)
        raise OSError(f"cannot write {str(tmp)!r} as an OpenEXR image: {exc}") from None


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
    header = _png_header(path)
    if header is not None:
        return 16 if header[2] == 16 else 8
    if _file_head(path, 4) == _EXR_MAGIC:
        return _exr_bits(path)
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
        (``pip install 'texsynth[exr]'``).

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
    header = _png_header(path)
    if _file_head(path, 4) in _TIFF_MAGIC:
        _check_tiff_size(path)
    if header is not None and header[2] == 16 and header[3] in (2, 4, 6):  # 16-bit colour: Pillow reads 8 bits
        data = _read_png16(path, header)
    elif _file_head(path, 4) == _EXR_MAGIC or path.suffix.lower() in _EXR:
        data = _read_exr(path)
    else:
        data = _read(path)
    if data.ndim == 3 and data.shape[-1] == 4 and _is_cmyk(path):
        data = _read(path, plugin="pillow", mode="RGB")
    if (data.ndim == 3 and data.shape[-1] > 4 and data.shape[0] > 1) or (data.ndim == 4 and data.shape[0] > 1):
        raise ValueError(f"{str(path)!r} holds {data.shape[0]} frames; use load_frames for animations")
    if data.ndim == 4 and data.shape[0] == 1:
        data = data[0]
    data = _supported_integers(data, path)
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


_RANGE_TOLERANCE = 1e-6  # as texsynth.core._validate: a float image may overshoot [0, 1] by this much


def _check_value_range(value_range):
    try:
        lo, hi = (float(v) for v in value_range)
    except (TypeError, ValueError):
        raise TypeError(f"value_range must be a pair of numbers (low, high), got {_short.repr(value_range)}") from None
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
    if not frames and suffix not in _EIGHT_BIT | _SIXTEEN_BIT | _EXR | {".npy"}:
        raise ValueError(
            f"path suffix {suffix!r} is not a supported image format; use one of "
            f"{sorted(_EIGHT_BIT | _SIXTEEN_BIT | _EXR | {'.npy'})}"
        )
    if suffix in _EXR and not frames:
        _openexr()  # an ImportError naming the extra, before any work
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
        (``pip install 'texsynth[exr]'``).

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
    bits = _check_bits(bits, allow_none=True, allowed=(8, 16, 32))
    suffix = path.suffix.lower()
    if suffix == ".npy":
        data = as_float_array(as_array(image, "image"), "image")
        prepare_target(path, overwrite)
        atomic_write(path, lambda tmp: _save_npy(tmp, data))
        return path
    check_suffix(path)
    if bits is None:
        bits = 16 if suffix in _SIXTEEN_BIT else 32 if suffix in _EXR else 8
    if bits == 8 and suffix in _EXR:
        raise ValueError("bits=8 cannot be stored in an .exr file (half or float samples); pass bits=16 (half) or "
                         "32 (float), or save as .png")
    if bits == 16 and suffix not in {".png", ".tif", ".tiff"} | _EXR:
        raise ValueError(f"bits=16 needs a .png, .tif or .exr path, got {suffix!r}")
    if bits == 32 and suffix not in _SIXTEEN_BIT | _EXR:
        raise ValueError(f"bits=32 (float32 samples) needs a .tif or .exr path, got {suffix!r}; pass bits=16 for a "
                         "16-bit PNG, or save as .tif")
    floats = bits == 32 or suffix in _EXR
    data = _float_samples(image)
    if not floats and np.issubdtype(data.dtype, np.floating) and (data.min() < 0 or data.max() > 1):
        lo, hi = float(data.min()), float(data.max())
        hint = "; or divide 0-255 data by 255" if hi > 1.5 and lo >= 0 else ""
        raise ValueError(f"image has values in [{lo:.6g}, {hi:.6g}] but a {suffix} file stores [0, 1]; save it as .exr "
                         f"or .tif with bits=32 to keep the values, or scale it in with "
                         f"texsynth.io.normalize_range{hint}")
    if suffix in _EXR and bits == 16 and float(np.abs(data).max()) > _HALF_MAX:
        raise ValueError(f"image has values up to {float(np.abs(data).max()):.6g} in magnitude, beyond the largest "
                         f"half float ({_HALF_MAX:g}); pass bits=32 for float32 samples")
    pixels = data.astype(np.float32) if floats else to_uint(data, bits)
    if pixels.ndim == 3 and pixels.shape[-1] == 1:
        pixels = pixels[..., 0]
    if suffix in _NO_ALPHA and pixels.ndim == 3 and pixels.shape[-1] in (2, 4):
        pixels = pixels[..., :-1] if pixels.shape[-1] == 4 else pixels[..., 0]
    prepare_target(path, overwrite)
    if suffix in _EXR:
        atomic_write(path, lambda tmp: _write_exr(tmp, pixels, bits))
    elif bits == 16 and suffix == ".png" and pixels.ndim == 3:  # imageio's Pillow writer has no 16-bit colour PNG
        atomic_write(path, lambda tmp: _write_png16(tmp, pixels))
    else:
        atomic_write(path, lambda tmp: _imwrite(tmp, pixels, extension=suffix))
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


def save_chunked(path, image, *, bits=None, overwrite=False, progress=False, attributes=None, zarr_format=None):
    """Write an image larger than memory block by block: a Zarr store or a tiled BigTIFF.

    Parameters
    ----------
    path : str or os.PathLike
        ``.zarr`` (a Zarr store: a folder, version 3 unless ``zarr_format=2``)
        or ``.tif``/``.tiff`` (a tiled BigTIFF, Deflate-compressed,
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
    attributes : dict, optional
        JSON-serialisable values (str keys) stored with the image: a Zarr
        store's attributes (``zarr.open_array(path).attrs``), a TIFF's JSON
        ImageDescription (``tifffile.TiffFile(path).shaped_metadata[0]``).
        ``texsynth_version`` is always added; the command line records
        ``method``, ``options``, ``seed`` and ``exemplar`` too.
    zarr_format : {None, 2, 3}
        ``.zarr`` only: the Zarr format version written (None: 3); 2 for
        readers that know only version 2 (zarr-python 2, older GDAL,
        Neuroglancer).

    Returns
    -------
    pathlib.Path
        The written path.

    Raises
    ------
    ValueError
        For another suffix, an image that is not ``(H, W[, C])``, values
        outside [0, 1] (found in the block that holds them; nothing is left
        behind), a ``bits`` outside 8, 16, 32, a ``zarr_format`` other than
        2 or 3 (or any for a TIFF).
    TypeError
        For ``attributes`` that is not a dict of JSON-serialisable values.
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
    if zarr_format is not None and suffix != ".zarr":
        raise ValueError(f"zarr_format is for .zarr stores, got {str(path)!r}; leave it None for a TIFF")
    if zarr_format is None:
        zarr_format = 3
    if isinstance(zarr_format, bool) or zarr_format not in (2, 3):
        raise ValueError(f"zarr_format must be 2 or 3 (or None: 3), got {zarr_format!r}")
    attributes = _check_attributes(attributes)
    if suffix != ".zarr" and "shape" in attributes:
        raise ValueError("attributes has a key 'shape', which a TIFF's JSON description keeps for the array's shape; "
                         "rename it")
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
        swap_folder(path, lambda tmp: _write_zarr(zarr, tmp, stored, progress, attributes, int(zarr_format)))
    else:
        atomic_write(path, lambda tmp: _write_tiff(tmp, stored, progress, attributes))
    return path


def _check_attributes(attributes):
    """``attributes`` with ``texsynth_version`` added, or a TypeError if it is not a JSON-serialisable dict."""
    import json

    from .core._version import __version__

    if attributes is None:
        attributes = {}
    if not isinstance(attributes, dict) or not all(isinstance(k, str) for k in attributes):
        raise TypeError(f"attributes must be a dict with str keys, got {_short.repr(attributes)}")
    try:
        text = json.dumps(attributes, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"attributes must hold JSON-serialisable values (str, numbers, lists, dicts): {exc}") from None
    return {**json.loads(text), "texsynth_version": __version__}


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


def _write_zarr(zarr, folder, stored, progress, attributes=None, zarr_format=3):
    # Zarr writes on threads of its own, which go on writing when an exception (SIGTERM, Ctrl-C) ends the main
    # thread's wait for them: a block landing after the clean-up would leave a partial store. So every Zarr
    # call runs on a thread of ours, which leaving the ``with`` waits for, before the store is removed.
    with ThreadPoolExecutor(1) as writer:
        array = writer.submit(zarr.create_array, store=str(folder), shape=stored.shape, dtype=stored.dtype,
                              chunks=tuple(c[0] for c in stored.chunks), zarr_format=zarr_format,
                              attributes=attributes or {}, overwrite=True).result()
        for r0, blocks in _block_rows(stored, progress):
            c0 = 0
            for block in blocks:
                region = (slice(r0, r0 + block.shape[0]), slice(c0, c0 + block.shape[1]))
                writer.submit(array.__setitem__, region, block).result()
                c0 += block.shape[1]


def _write_tiff(tmp, stored, progress, attributes=None):
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
                     extrasamples=("unassalpha",) if channels in (2, 4) else None,
                     metadata=attributes or {})


# --------------------------------------------------------------------------- #
# source-coordinate maps
# --------------------------------------------------------------------------- #
_MAP_ARRAYS = ("coordinates", "weights", "source_index")
# image files for a map: 16-bit PNG, float32 TIFF, float32 EXR; R = (col + 0.5) / width, G = (row + 0.5) / height
_MAP_IMAGES = {".png", ".tif", ".tiff", ".exr"}
_MAP_KEY = "texsynth"  # the PNG tEXt keyword / EXR header attribute / TIFF JSON description key of the map's metadata
_PNG_MAP_LARGEST = 32768  # exemplar sides a 16-bit PNG map addresses exactly (1/65535 steps, < half a pixel)


def _map_suffix(path):
    suffix = path.suffix.lower()
    if suffix != ".npz" and suffix not in _MAP_IMAGES:
        raise ValueError(f"a source-coordinate map is saved as .npz (every slot and weight), or as an image: .png "
                         f"(16 bits), .tif (float32) or .exr (float32); got {str(path)!r}")
    return suffix


def _check_exemplar_size(exemplar_size):
    if isinstance(exemplar_size, numbers.Integral) and not isinstance(exemplar_size, bool):
        exemplar_size = (exemplar_size, exemplar_size)
    try:
        h, w = exemplar_size
        ok = all(isinstance(v, numbers.Integral) and not isinstance(v, bool) and v >= 1 for v in (h, w))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"exemplar_size must be the exemplar's (height, width) in pixels (or an int), got "
                         f"{_short.repr(exemplar_size)}; pass exemplar.shape[:2]")
    return int(h), int(w)


def _encode_map(coords, size, suffix):
    """``(H, W, 2)`` (row, col) coordinates as RGB(A) samples in [0, 1] (alpha 0 where the map has no source)."""
    h, w = size
    missing = np.any(coords < 0, axis=-1)
    rows, cols = coords[..., 0], coords[..., 1]
    if np.any(rows[~missing] >= h) or np.any(cols[~missing] >= w):
        raise ValueError(f"coordinates point outside the exemplar of exemplar_size={size}: rows up to "
                         f"{int(rows.max())}, columns up to {int(cols.max())}; pass the size of the exemplar the "
                         "map was made from")
    kind = np.float64 if suffix == ".png" else np.float32
    samples = np.zeros(coords.shape[:2] + (4 if missing.any() else 3,), kind)
    samples[..., 0] = (cols + 0.5) / w
    samples[..., 1] = (rows + 0.5) / h
    if missing.any():
        samples[..., 3] = ~missing
        samples[missing, :2] = 0
    return samples


def _decode_map(samples, size):
    """:func:`_encode_map` undone: ``(H, W, 2)`` int64 (row, col), -1 where alpha < 0.5."""
    h, w = size
    cols = np.clip(np.floor(samples[..., 0].astype(np.float64) * w), 0, w - 1).astype(np.int64)
    rows = np.clip(np.floor(samples[..., 1].astype(np.float64) * h), 0, h - 1).astype(np.int64)
    coords = np.stack([rows, cols], axis=-1)
    if samples.shape[-1] == 4:
        coords[samples[..., 3] < 0.5] = -1
    return coords


def _save_map_image(path, suffix, coords, size, overwrite):
    import json

    if suffix == ".png" and max(size) > _PNG_MAP_LARGEST:
        raise ValueError(f"a 16-bit PNG map addresses exemplars up to {_PNG_MAP_LARGEST} pixels a side exactly, got "
                         f"exemplar_size={size}; save the map as .exr or .tif (float32)")
    samples = _encode_map(coords, size, suffix)
    note = json.dumps({"exemplar_size": list(size), "encoding": "R = (col + 0.5) / width, G = (row + 0.5) / height, "
                       "origin top left; A = 0: no source"})
    prepare_target(path, overwrite)
    if suffix == ".png":
        pixels = to_uint(samples, 16)
        atomic_write(path, lambda tmp: _write_png16(tmp, pixels, {_MAP_KEY: note}))
    elif suffix == ".exr":
        atomic_write(path, lambda tmp: _write_exr(tmp, samples, 32, {_MAP_KEY: note}))
    else:
        import tifffile

        atomic_write(path, lambda tmp: tifffile.imwrite(
            tmp, samples, photometric="rgb", compression="zlib", metadata={_MAP_KEY: json.loads(note)},
            extrasamples=("unassalpha",) if samples.shape[-1] == 4 else None))


def _map_image_size(path, suffix):
    """The exemplar size a map image records, or None (a file re-saved by another program)."""
    import json

    note = None
    try:
        if suffix == ".png":
            note = _png_text(path).get(_MAP_KEY)
        elif suffix == ".exr":
            note = _open_exr(path, header_only=True).header().get(_MAP_KEY)
        else:
            import tifffile

            with tifffile.TiffFile(path) as tif:
                found = (tif.shaped_metadata or [{}])[0].get(_MAP_KEY)
            note = None if found is None else json.dumps(found)
        size = json.loads(note)["exemplar_size"] if note else None
        return None if size is None else _check_exemplar_size(tuple(size))
    except (ValueError, KeyError, TypeError, OSError):
        return None


def save_coordinates(path, coordinates, weights=None, *, source_index=None, exemplar_size=None, overwrite=False):
    """Write a source-coordinate map atomically: a ``.npz`` file, or an image for a shader.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file (every slot, weight and source index: the exact map),
        or an image: ``.png`` (16-bit RGB), ``.tif`` (float32 RGB) or ``.exr``
        (float32 RGB, with the ``exr`` extra). An image holds one exemplar
        pixel per output pixel, normalised by the exemplar's size: R =
        ``(col + 0.5) / width`` and G = ``(row + 0.5) / height`` (texel
        centres, origin at the top left: a shader's UV with ``v`` down), B =
        0, and an alpha channel, 0 where a pixel has no source (-1 in the
        map), only when there are such pixels. A blend map (``K`` sources a
        pixel) is stored as its dominant source, ``coordinates[:, :, 0]``.
    coordinates : array_like or info
        The map (``docs/conventions.md``), or an info of a synthesis, whose
        ``coordinates``, ``weights`` and ``source_index`` are saved; a video
        map of :func:`texsynth.patchwork_video` (``(N, H, W, K, 2)``) too
        (``.npz`` only).
    weights, source_index : array_like, optional
        As in :func:`texsynth.apply_coordinates` (taken from the info when
        ``coordinates`` is one). A map with ``source_index`` (several
        exemplars) is saved as ``.npz`` only.
    exemplar_size : int or (int, int), optional
        The exemplar's ``(height, width)``: needed for an image (whose
        values are divided by it, and which records it), unused by ``.npz``.
    overwrite : bool
        Replace an existing file.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    ValueError, TypeError
        For a map :func:`texsynth.apply_coordinates` would refuse, another
        suffix, an image without ``exemplar_size`` (or of a map of several
        exemplars or frames, or coordinates outside ``exemplar_size``), or
        an existing file without ``overwrite``.

    Examples
    --------
    >>> import tempfile, texsynth
    >>> from texsynth import data
    >>> out, info = texsynth.quilt(data.load("bread")[:48, :48], 64, block=16, rng=0, return_info=True)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     saved = load_coordinates(save_coordinates(d + "/map.npz", info))
    ...     as_png = load_coordinates(save_coordinates(d + "/map.png", info, exemplar_size=48))
    >>> bool(np.array_equal(texsynth.apply_coordinates(data.load("bread")[:48, :48], saved), out))
    True
    >>> bool(np.array_equal(as_png.coordinates, info.coordinates))
    True
    """
    from .core.coordinates import check_map, check_sources, video_map

    path = as_path(path)
    suffix = _map_suffix(path)
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
    check_bool(overwrite, "overwrite")
    if suffix in _MAP_IMAGES:
        if np.ndim(coordinates) == 5 or source_index is not None:
            what = "a video map" if np.ndim(coordinates) == 5 else "a map of several exemplars (source_index)"
            raise ValueError(f"{what} cannot be saved as an image, which holds one exemplar's coordinates; save it "
                             f"as .npz, got {str(path)!r}")
        if exemplar_size is None:
            raise ValueError(f"an image map stores coordinates divided by the exemplar's size; pass "
                             f"exemplar_size=exemplar.shape[:2] to save {str(path)!r}")
        if suffix == ".exr":
            _openexr()
        _save_map_image(path, suffix, coords[:, :, 0], _check_exemplar_size(exemplar_size), overwrite)
        return path
    arrays = {"coordinates": as_array(coordinates, "coordinates")}
    if w is not None:
        arrays["weights"] = as_array(weights, "weights")
    if source_index is not None:
        arrays["source_index"] = as_array(source_index, "source_index")
    prepare_target(path, overwrite)

    def write(tmp):
        with open(tmp, "wb") as f:  # a file object: np.savez would append ".npz" to another name
            np.savez_compressed(f, **arrays)

    atomic_write(path, write)
    return path


def load_coordinates(path, *, exemplar_size=None):
    """Read a map written by :func:`save_coordinates` (a ``.npz`` file or an image).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` map, or an image map (``.png``, ``.tif``, ``.exr``) in the
        layout :func:`save_coordinates` describes, also one re-saved or
        painted in another program (any bit depth :func:`load_image` reads).
    exemplar_size : int or (int, int), optional
        Image maps only: the exemplar's ``(height, width)``, needed when the
        file does not record it (texsynth's own maps do: PNG tEXt, TIFF
        description, EXR header); if both are there, they must agree.

    Returns
    -------
    types.SimpleNamespace
        ``coordinates``, ``weights`` and ``source_index`` (the last two None
        when not saved, and always for an image map, whose ``coordinates``
        are ``(H, W, 2)`` int64): pass it to :func:`texsynth.apply_coordinates`
        as the map.

    Raises
    ------
    ValueError
        If the file is not a map (missing ``coordinates``, other arrays; an
        image without two colour channels), an image map's exemplar size is
        unknown or disagrees with ``exemplar_size``, or ``exemplar_size`` is
        given for a ``.npz`` map.
    """
    from types import SimpleNamespace

    path = as_path(path)
    suffix = _map_suffix(path)
    if suffix in _MAP_IMAGES:
        recorded = _map_image_size(path, suffix) if path.is_file() else None
        given = None if exemplar_size is None else _check_exemplar_size(exemplar_size)
        if recorded is not None and given is not None and recorded != given:
            raise ValueError(f"{str(path)!r} is a map of an exemplar of {recorded[1]}x{recorded[0]} pixels, but "
                             f"exemplar_size={given} was given; pass channels of the exemplar's size")
        size = recorded or given
        samples = load_image(path)
        if size is None:
            raise ValueError(f"{str(path)!r} does not record the exemplar's size (a file saved by another program?); "
                             "pass exemplar_size=(height, width) of the exemplar the map was made from")
        if samples.ndim != 3 or samples.shape[-1] < 3:
            channels = 1 if samples.ndim == 2 else samples.shape[-1]
            raise ValueError(f"{str(path)!r} is not a coordinate map: it has {channels} channel(s), where a map has "
                             "R (column), G (row), B and optionally A")
        if image_bits(path) == 8 and max(size) > 255:
            raise ValueError(f"{str(path)!r} is an 8-bit image, which cannot address the pixels of a "
                             f"{size[1]}x{size[0]} exemplar exactly; save the map as a 16-bit PNG, .tif or .exr")
        return SimpleNamespace(coordinates=_decode_map(samples, size), weights=None, source_index=None)
    if exemplar_size is not None:
        raise ValueError(f"exemplar_size is for image maps; {str(path)!r} is a .npz map, which holds exemplar "
                         "pixels as they are: pass exemplar_size=None")
    with np.load(path, allow_pickle=False) as data:
        unknown = sorted(set(data.files) - set(_MAP_ARRAYS))
        if "coordinates" not in data.files or unknown:
            raise ValueError(f"{str(path)!r} is not a source-coordinate map (it holds {sorted(data.files)}); pass a "
                             "file written by texsynth.io.save_coordinates or texsynth ... --coordinates")
        return SimpleNamespace(**{name: (data[name] if name in data.files else None) for name in _MAP_ARRAYS})
