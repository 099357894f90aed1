"""Frame sequences: load_frames and save_frames (animated GIF, a folder of PNG frames, video files)."""

from __future__ import annotations

import importlib.util
import re

import imageio.v3 as iio
import numpy as np

from ..core._extras import install_hint
from ..core._validate import as_array, as_float_array, as_image, check_bool, check_positive_float
from ..core.files import as_path, atomic_write, prepare_target, swap_folder
from ._formats import EIGHT_BIT, EXR, GIF_MAX_DELAY_MS, SIXTEEN_BIT, read, supported_integers
from ._images import check_suffix, imwrite, load_image, to_uint


def load_frames(path):
    """Read a frame sequence as ``(T, H, W, C)`` float in [0, 1].

    Parameters
    ----------
    path : str or os.PathLike
        An animated GIF, a folder of still images (PNG, TIFF, EXR, ...; read in
        sorted name order), or a video file (``.mp4``, ``.avi``, ...; needs the ``video`` extra,
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
        files = sorted(p for p in path.iterdir() if p.suffix.lower() in EIGHT_BIT | SIXTEEN_BIT | EXR)
        if not files:
            raise ValueError(f"folder {str(path)!r} contains no image files")
        frames = [load_image(p) for p in files]
        shapes = {f.shape for f in frames}
        if len(shapes) != 1:
            raise ValueError(f"frames in {str(path)!r} have different shapes {sorted(shapes)}")
        data = np.stack(frames)
    elif path.is_file():
        is_gif = path.suffix.lower() == ".gif"
        hint = "" if is_gif else f" (videos need: {install_hint('video')})"
        try:
            raw = iio.imread(path, index=None)
        except Exception as exc:
            if not is_gif:
                raise ValueError(f"cannot read {str(path)!r} as frames: {exc}{hint}") from None
            # a GIF with transparency decodes to RGB and RGBA frames: read all as RGBA
            raw = read(path, "frames", index=None, mode="RGBA")
            if np.all(raw[..., 3] == 255):
                raw = raw[..., :3]
        if raw.ndim == 2 or (raw.ndim == 3 and not is_gif and raw.shape[-1] <= 4):
            raw = raw[None]
        if raw.ndim == 4 and raw.shape[-1] == 3 and _is_grey(raw):
            raw = raw[..., :1]  # GIF stores grey frames as palette RGB: give back C == 1
        raw = supported_integers(raw, path)
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
        atomic_write(path, lambda tmp: imwrite(tmp, pixels, extension=".png",
                                               duration=1000.0 / fps, loop=0 if loop else 1))
        return path
    if pixels.ndim == 4 and pixels.shape[-1] in (2, 4):  # GIF and video store no alpha
        pixels = pixels[..., :-1] if pixels.shape[-1] == 4 else pixels[..., 0]
    if suffix == ".gif":
        duration = 1000.0 / fps
        if duration > GIF_MAX_DELAY_MS:
            raise ValueError(
                f"fps={fps:g} is too slow for a GIF, whose longest frame delay is 655.35 s; "
                f"pass fps >= {1000.0 / GIF_MAX_DELAY_MS:.5f} or save a folder of PNG frames"
            )
        prepare_target(path, overwrite)
        atomic_write(path, lambda tmp: imwrite(tmp, pixels, extension=".gif",
                                               duration=duration, loop=0 if loop else 1))
        return path
    if importlib.util.find_spec("imageio_ffmpeg") is None:
        raise ValueError(
            f"path {str(path)!r}: writing {suffix!r} videos needs the video extra "
            f"({install_hint('video')}); or save as .gif or a folder of PNG frames"
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
            imwrite(tmp / f"frame_{t:04d}.png", frame, extension=".png")

    swap_folder(path, write)
