"""Outputs larger than memory, chunk by chunk: lazy images on ``dask.array``.

Some methods compute each output pixel from a bounded neighbourhood and a
global random layout drawn once: the procedurals (Perlin noise evaluated at
any point), Harrison's patchwork (a jittered grid of cells and their sources)
and tiling and blending (a hashed triangle grid). Their ``chunks=`` option
returns a :class:`dask.array.Array` whose blocks are rendered on demand by
``render(rows, cols)``, with ``rows`` and ``cols`` the block's half-open
slices of the whole output. Nothing the size of the output is ever
allocated: write the array with :func:`texsynth.io.save_chunked` (Zarr or a
tiled BigTIFF) or compute any part of it. Each method's block is
bit-identical to the same pixels of its in-memory result.

Dask is an optional dependency (``pip install '.[dask]'`` in a checkout); without it,
``chunks=`` raises an ImportError that says so.
"""

from __future__ import annotations

import numpy as np

from ._extras import install_hint
from ._validate import check_memory, check_positive_int, max_threads

__all__ = ["as_chunks", "chunked_image", "require_dask"]


def require_dask(what="chunks="):
    """``dask.array``, or an ImportError that names the extra to install."""
    try:
        import dask.array as da
    except ImportError:  # pragma: no cover - dask is in the test extra
        raise ImportError(f"{what} needs Dask: {install_hint('dask')}") from None
    return da


def as_chunks(chunks, size, name="chunks"):
    """The block shape ``(rows, cols)`` of ``chunks``: an int (square blocks) or ``(rows, cols)``.

    A block larger than the output is cut to it.

    >>> as_chunks(1024, (3000, 500))
    (1024, 500)
    """
    if isinstance(chunks, (tuple, list)):
        if len(chunks) != 2:
            raise ValueError(f"{name} must be an int or (rows, cols), got {chunks!r}")
        rows, cols = (check_positive_int(c, name) for c in chunks)
    else:
        rows = cols = check_positive_int(chunks, name)
    return min(rows, size[0]), min(cols, size[1])


def chunked_image(size, channels, dtype, chunks, render, *, bytes_per_pixel, name="chunks"):
    """A lazy ``(H, W[, C])`` image whose block over ``rows, cols`` (slices) is ``render(rows, cols)``.

    Parameters
    ----------
    size : (int, int)
        ``(H, W)`` of the whole output.
    channels : int or None
        ``C``, or None for a grey ``(H, W)`` output.
    dtype : numpy.dtype
        The blocks' dtype.
    chunks : int or (int, int)
        Block shape (see :func:`as_chunks`).
    render : callable
        ``render(rows, cols)`` returns the block, ``(len rows, len cols[, C])``.
    bytes_per_pixel : float
        Working memory of ``render`` per block pixel, for the pre-flight check:
        one block per thread of Dask's default scheduler must fit.

    Returns
    -------
    dask.array.Array
    """
    da = require_dask()
    rows, cols = as_chunks(chunks, size, name)
    check_memory(float(rows) * cols * bytes_per_pixel * max_threads(), (rows, cols), name,
                 "one block per thread (the working memory of rendering a block)")
    shape = tuple(size) + (() if channels is None else (channels,))
    block_shape = (rows, cols) + (() if channels is None else (channels,))
    normal = da.core.normalize_chunks(block_shape, shape=shape)

    def block(block_info=None):
        (r0, r1), (c0, c1) = block_info[None]["array-location"][:2]
        return render(slice(r0, r1), slice(c0, c1))

    return da.map_blocks(block, chunks=normal, dtype=dtype, meta=np.empty((0,) * len(shape), dtype))
