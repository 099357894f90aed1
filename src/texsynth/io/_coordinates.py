"""Coordinate maps: save_coordinates and load_coordinates (.npz, and 16-bit PNG, TIFF and EXR images)."""

from __future__ import annotations

import numbers

import numpy as np

from ..core._validate import as_array, check_bool
from ..core.files import as_path, atomic_write, prepare_target
from ._formats import open_exr, openexr, png_text, short, write_exr, write_png16
from ._images import image_bits, load_image, to_uint


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
                         f"{short.repr(exemplar_size)}; pass exemplar.shape[:2]")
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
        atomic_write(path, lambda tmp: write_png16(tmp, pixels, {_MAP_KEY: note}))
    elif suffix == ".exr":
        atomic_write(path, lambda tmp: write_exr(tmp, samples, 32, {_MAP_KEY: note}))
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
            note = png_text(path).get(_MAP_KEY)
        elif suffix == ".exr":
            note = open_exr(path, header_only=True).header().get(_MAP_KEY)
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
    from ..core.coordinates import check_map, check_sources, video_map

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
            openexr()
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
