"""Images larger than memory: save_chunked writes a lazy (Dask) or in-memory image to Zarr or a tiled TIFF."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ..core._validate import as_array, check_bool
from ..core.files import as_path, atomic_write, prepare_target, swap_folder
from ._formats import check_bits, short
from ._images import to_uint
from ..core._extras import install_hint


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
        (``python -m pip install '.[dask]'`` in a checkout installs both).

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
    from ..core.chunked import require_dask

    path = as_path(path)
    overwrite = check_bool(overwrite, "overwrite")
    bits = check_bits(bits, allow_none=True, allowed=(8, 16, 32))
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
            raise ImportError(f"writing .zarr needs Zarr: {install_hint('dask')}") from None
        swap_folder(path, lambda tmp: _write_zarr(zarr, tmp, stored, progress, attributes, int(zarr_format)))
    else:
        atomic_write(path, lambda tmp: _write_tiff(tmp, stored, progress, attributes))
    return path


def _check_attributes(attributes):
    """``attributes`` with ``texsynth_version`` added, or a TypeError if it is not a JSON-serialisable dict."""
    import json

    from ..core._version import __version__

    if attributes is None:
        attributes = {}
    if not isinstance(attributes, dict) or not all(isinstance(k, str) for k in attributes):
        raise TypeError(f"attributes must be a dict with str keys, got {short.repr(attributes)}")
    try:
        text = json.dumps(attributes, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"attributes must hold JSON-serialisable values (str, numbers, lists, dicts): {exc}") from None
    return {**json.loads(text), "texsynth_version": __version__}


def _block_rows(stored, progress):
    """Yield ``(row start, blocks)`` per row of blocks, each row computed at once (its blocks in parallel)."""
    import dask

    from ..core._progress import Progress

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
