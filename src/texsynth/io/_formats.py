"""File formats of texsynth.io: the format families by suffix, a 16-bit PNG codec (zlib and numpy), OpenEXR
through the optional OpenEXR package, and the checks of what imageio reads (CMYK, TIFF size, integer types)."""

from __future__ import annotations

import importlib.util
import numbers
import reprlib
import struct
import zlib

import imageio.v3 as iio
import numpy as np

from ..core._extras import install_hint


EIGHT_BIT = {".png", ".jpg", ".jpeg", ".gif", ".bmp", ".ppm", ".pgm", ".webp", ".tga"}
SIXTEEN_BIT = {".tif", ".tiff"}
EXR = {".exr"}  # half (bits=16) or float32 (bits=32) samples, through the OpenEXR package (the exr extra)
EXR_MAGIC = b"\x76\x2f\x31\x01"
HALF_MAX = 65504.0  # the largest finite half-float
# formats that store no alpha channel: an alpha channel is dropped (documented in save_image)
NO_ALPHA = {".jpg", ".jpeg", ".bmp", ".ppm", ".pgm", ".gif"}
# frame-sequence containers written through imageio-ffmpeg (the ``video`` extra)
# the containers imageio's ffmpeg writer fills with its default codec (H.264 or MPEG-4); .m4v, .mpg and .flv
# go to other imageio plugins, and WebM does not take H.264
VIDEO = {".mp4", ".mov", ".avi", ".mkv", ".mpeg", ".wmv"}
# a GIF frame delay is a 16-bit count of centiseconds
GIF_MAX_DELAY_MS = 655_350
# file signatures of formats whose samples are unsigned and at most 16 bits (PNG, Netpbm P1-P7):
# Pillow hands their 16-bit samples over as int32 (16-bit Netpbm scaled to 0..65535)
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_NETPBM_MAGIC = tuple(f"P{k}".encode() for k in range(1, 8))
TIFF_MAGIC = (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")  # little/big-endian TIFF and BigTIFF

short = reprlib.Repr()


# --------------------------------------------------------------------------- #
# argument checks
# --------------------------------------------------------------------------- #
def check_bits(bits, *, allow_none, allowed=(8, 16)):
    if bits is None and allow_none:
        return None
    words = ", ".join(map(str, allowed[:-1])) + f" or {allowed[-1]}"
    choices = f"None, {words}" if allow_none else words
    if not isinstance(bits, numbers.Integral) or isinstance(bits, (bool, np.bool_)):
        raise TypeError(f"bits must be {choices}, got {type(bits).__name__} {short.repr(bits)}")
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


def write_png16(path, pixels, text=None):
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


def png_text(path):
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


def file_head(path, n):
    """The first ``n`` bytes of a file (fewer if it is shorter; none if it cannot be read)."""
    try:
        with open(path, "rb") as f:
            return f.read(n)
    except OSError:
        return b""


def png_header(path):
    """``(width, height, bit depth, colour type, interlace)`` of a PNG file, or None for another file."""
    head = file_head(path, 33)
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


def read_png16(path, header):
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


def openexr():
    """The ``OpenEXR`` module, or an ImportError naming the extra that installs it."""
    try:
        import OpenEXR
    except ImportError:
        raise ImportError(f"reading and writing .exr files needs the OpenEXR package: {install_hint('exr')}; "
                          "or use a float TIFF (.tif, bits=32)") from None
    return OpenEXR


def _has_openexr():
    return importlib.util.find_spec("OpenEXR") is not None


def open_exr(path, header_only=False):
    OpenEXR = openexr()
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


def read_exr(path):
    """An EXR file's first part as float32 ``(H, W)`` or ``(H, W, C)`` (half samples widened to float32)."""
    f = open_exr(path)
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


def exr_bits(path):
    """16 for an EXR file whose channels are all half floats, else 32."""
    channels = open_exr(path).channels()
    names = _exr_layout(path, list(channels))
    return 16 if all(np.asarray(channels[n].pixels).dtype == np.float16 for n in names) else 32


def write_exr(tmp, samples, bits, attributes=None):
    """Write float samples ``(H, W[, C])`` as a ZIP-compressed scanline EXR (half for ``bits=16``)."""
    OpenEXR = openexr()
    planes = samples[..., None] if samples.ndim == 2 else samples
    kind = np.float16 if bits == 16 else np.float32
    channels = {name: np.ascontiguousarray(planes[..., k], dtype=kind)
                for k, name in enumerate(_EXR_CHANNELS[planes.shape[-1]])}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, **(attributes or {})}
    try:
        OpenEXR.File(header, channels).write(str(tmp))
    except RuntimeError as exc:  # OpenEXR's write errors (a full disk, a read-only folder)
        raise OSError(f"cannot write {str(tmp)!r} as an OpenEXR image: {exc}") from None


# --------------------------------------------------------------------------- #
# loading
# --------------------------------------------------------------------------- #
def read(path, what="an image", **kwargs):
    try:
        return iio.imread(path, **kwargs)
    except Exception as exc:  # imageio raises many types; one clear message
        raise ValueError(f"cannot read {str(path)!r} as {what}: {exc}") from None


def is_cmyk(path):
    """Whether Pillow opens ``path`` as a CMYK image (JPEG and TIFF from print workflows)."""
    try:
        return iio.immeta(path, plugin="pillow").get("mode") == "CMYK"
    except Exception:  # not a format Pillow reads: then imageio's reader is the only one
        return False


def check_tiff_size(path):
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


def holds_at_most_16_bits(path):
    """Whether the file is a PNG or Netpbm file: unsigned samples of at most 16 bits, by the format."""
    head = file_head(path, 8)
    return head.startswith(_PNG_MAGIC) or head[:2] in _NETPBM_MAGIC


def supported_integers(data, path):
    """uint8/uint16 as is; the int32 Pillow gives for 16-bit PNG/Netpbm as uint16; refuse other integers."""
    kind = data.dtype
    if not np.issubdtype(kind, np.integer) or kind in (np.uint8, np.uint16):
        return data
    lo, hi = (int(data.min()), int(data.max())) if data.size else (0, 0)
    if kind == np.int32 and holds_at_most_16_bits(path) and 0 <= lo and hi <= 65535:
        return data.astype(np.uint16)
    raise ValueError(
        f"path {str(path)!r} holds {kind} pixels (values {lo}..{hi}): signed and wider-than-16-bit integers have "
        "no agreed white level, so texsynth does not guess one. Convert the file to 8- or 16-bit unsigned "
        "(or float in [0, 1]), or read it yourself (imageio.v3.imread) and divide it by its white level "
        "(e.g. 4095 for 12-bit sensor data) before passing the array"
    )
