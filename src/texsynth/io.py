"""Loading and saving images, volumes and frame sequences.

Loading converts to float in [0, 1] with the conventions of
:mod:`texsynth.core._validate`. Saving converts float [0, 1] to the file type's
integer format (uint8 for PNG/JPEG/GIF/BMP, uint16 for 16-bit PNG and TIFF),
writes to a temporary name next to the target and renames it, so a file is
never half-written. Nothing is overwritten unless ``overwrite=True``.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import tempfile
from pathlib import Path

import imageio.v3 as iio
import numpy as np

from .core._validate import as_float_array, as_image

__all__ = ["load_image", "save_image", "load_frames", "save_frames", "to_uint"]

_EIGHT_BIT = {".png", ".jpg", ".jpeg", ".gif", ".bmp", ".ppm", ".pgm", ".webp"}
_SIXTEEN_BIT = {".tif", ".tiff"}


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
        last channel), float64 in [0, 1].

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file cannot be read as an image.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"path {str(path)!r} does not exist or is not a file")
    try:
        data = iio.imread(path)
    except Exception as exc:  # imageio raises many types; one clear message
        raise ValueError(f"cannot read {str(path)!r} as an image: {exc}") from None
    if data.ndim == 3 and data.shape[-1] > 4 and data.shape[0] > 1:
        raise ValueError(f"{str(path)!r} holds {data.shape[0]} frames; use load_frames for animations")
    if data.ndim == 4 and data.shape[0] == 1:
        data = data[0]
    if data.dtype not in (np.uint8, np.uint16, np.bool_) and np.issubdtype(data.dtype, np.integer):
        data = data.astype(np.uint16) if data.max() > 255 else data.astype(np.uint8)
    return as_image(data, name=f"image in {path.name}")


def to_uint(image, bits=8):
    """Convert float [0, 1] data to uint8 or uint16 by rounding (values are clipped).

    >>> to_uint(np.array([0.0, 0.5, 1.0]))
    array([  0, 128, 255], dtype=uint8)
    """
    if bits not in (8, 16):
        raise ValueError(f"bits must be 8 or 16, got {bits!r}")
    top = 255 if bits == 8 else 65535
    data = np.clip(np.asarray(image, dtype=np.float64), 0.0, 1.0)
    return np.round(data * top).astype(np.uint8 if bits == 8 else np.uint16)


def _prepare_target(path, overwrite):
    path = Path(path)
    if path.exists() and not overwrite:
        raise FileExistsError(f"{str(path)!r} already exists; pass overwrite=True to replace it")
    if not path.parent.exists():
        raise FileNotFoundError(f"folder {str(path.parent)!r} does not exist; create it first")
    return path


def _atomic_write(path, write):
    """Call ``write(tmp_path)`` on a temporary file beside ``path``, then rename it."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def save_image(path, image, *, bits=None, overwrite=False):
    """Write an image atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Target file; its suffix chooses the format. ``.npy`` stores the float
        array unchanged (useful for volumes).
    image : array_like
        Float in [0, 1] (or uint8/uint16/bool), ``(H, W)`` or ``(H, W, C)``.
    bits : {None, 8, 16}
        Integer depth; None means 16 for TIFF, 8 for everything else.
    overwrite : bool
        Replace an existing file. Off by default: nothing is replaced by surprise.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    path = _prepare_target(path, overwrite)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        data = as_float_array(image, "image")
        _atomic_write(path, lambda tmp: np.save(tmp, data))
        return path
    data = as_image(image, "image")
    if bits is None:
        bits = 16 if suffix in _SIXTEEN_BIT else 8
    if suffix not in _EIGHT_BIT | _SIXTEEN_BIT:
        raise ValueError(
            f"path suffix {suffix!r} is not a supported image format; use one of "
            f"{sorted(_EIGHT_BIT | _SIXTEEN_BIT | {'.npy'})}"
        )
    if bits == 16 and suffix not in {".png", ".tif", ".tiff"}:
        raise ValueError(f"bits=16 needs a .png or .tif path, got {suffix!r}")
    pixels = to_uint(data, bits)
    if pixels.ndim == 3 and pixels.shape[-1] == 1:
        pixels = pixels[..., 0]
    if suffix in {".jpg", ".jpeg"} and pixels.ndim == 3 and pixels.shape[-1] in (2, 4):
        pixels = pixels[..., :-1] if pixels.shape[-1] == 4 else pixels[..., 0]
    _atomic_write(path, lambda tmp: iio.imwrite(tmp, pixels, extension=suffix))
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
    """
    path = Path(path)
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
        try:
            raw = iio.imread(path, index=None)
        except Exception as exc:
            hint = " (videos need: pip install 'texsynth[video]')" if path.suffix.lower() not in {".gif"} else ""
            raise ValueError(f"cannot read {str(path)!r} as frames: {exc}{hint}") from None
        if raw.ndim == 2 or (raw.ndim == 3 and path.suffix.lower() != ".gif" and raw.shape[-1] <= 4):
            raw = raw[None]
        if raw.ndim == 4 and raw.shape[-1] == 3 and _is_grey(raw):
            raw = raw[..., :1]  # GIF stores grey frames as palette RGB: give back C == 1
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
        ``.gif`` for an animated GIF, ``.mp4`` (needs the ``video`` extra), or
        a path without suffix for a folder of PNG frames ``frame_0000.png``...
    frames : array_like
        ``(T, H, W)`` or ``(T, H, W, C)`` in [0, 1].
    fps : float
        Frames per second.
    loop : bool
        GIF only: loop forever.
    overwrite : bool
        Replace an existing file, or a folder that holds nothing but the
        ``frame_NNNN.png`` files of an earlier save (a folder with other files
        is refused, so a user's files are never deleted).

    Returns
    -------
    pathlib.Path
    """
    path = _prepare_target(path, overwrite)
    data = as_image(frames, "frames", spatial_dims=3)
    pixels = to_uint(data, 8)
    if pixels.ndim == 4 and pixels.shape[-1] == 1:
        pixels = pixels[..., 0]
    suffix = path.suffix.lower()
    if suffix == "":
        _write_frame_folder(path, pixels)
        return path
    if suffix == ".gif":
        duration = 1000.0 / float(fps)
        _atomic_write(path, lambda tmp: iio.imwrite(tmp, pixels, extension=".gif",
                                                    duration=duration, loop=0 if loop else 1))
        return path
    if importlib.util.find_spec("imageio_ffmpeg") is None:
        raise ValueError(
            f"path {str(path)!r}: writing {suffix!r} videos needs the video extra "
            "(pip install 'texsynth[video]'); or save as .gif or a folder of PNG frames"
        )
    try:
        _atomic_write(path, lambda tmp: iio.imwrite(tmp, pixels, extension=suffix, fps=fps))
    except Exception as exc:
        raise ValueError(f"cannot write {str(path)!r} as a video: {exc}") from None
    return path


_FRAME_NAME = re.compile(r"frame_\d{4,}\.png")


def _write_frame_folder(path, pixels):
    """Write ``frame_0000.png``... into a new folder, then swap it in for ``path``.

    An existing folder is replaced only if it holds nothing but frames that
    :func:`save_frames` wrote, so a user's other files are never deleted.
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
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}-", dir=path.parent))
    old = None
    try:
        for t, frame in enumerate(pixels):
            iio.imwrite(tmp / f"frame_{t:04d}.png", frame)
        if path.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}-old-", dir=path.parent))
            os.replace(path, old / path.name)
        os.replace(tmp, path)
    except BaseException:
        if old is not None and not path.exists():
            os.replace(old / path.name, path)
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
