"""Source-coordinate maps: re-render any channel of the exemplar through a synthesis.

Every patch and pixel method can return (``return_info=True``) where each
output pixel came from in the exemplar: ``info.coordinates``. With it, one
synthesis of the albedo gives the matching normal, roughness and height maps,
because :func:`apply_coordinates` copies (or blends) each of those channels
exactly as the synthesis copied (or blended) the albedo.

The shape convention, the same for every method (``docs/conventions.md``):

- ``coordinates``: ``(H, W, 2)`` integers, the exemplar pixel ``(row, col)``
  each output pixel was copied from; ``weights`` is None. Methods that copy
  pixels (image quilting, graph cuts, Wang tiles, Efros-Leung, Wei-Levoy,
  texture optimization's dominant neighbourhood) give this.
- ``coordinates``: ``(H, W, K, 2)`` with ``weights`` ``(H, W, K)``: the
  ``K`` exemplar pixels an output pixel blends, the largest weight first
  (``coordinates[:, :, 0]`` is therefore always a valid ``(H, W, 2)`` map
  of the dominant source). Unused slots have weight 0. Methods that blend
  (patch-based sampling's feathered zones, patchwork) give this.
- with ``source_index`` ``(H, W, K)``: the source each slot points into
  (``mix_textures``' exemplars), or -1 for the average of the sources'
  images; each channel is then a list of images, one per source.
- a video map (``patchwork_video``): ``(N, H, W, K, 2)`` with weights and
  ``source_index`` ``(N, H, W, K)``, one map per output frame; the sources
  are the input frames (-1: their average frame ``A`` of eq. 6).

A pixel is rendered as

.. math:: O(x) = \\sum_k w_k(x)\\, I(c_k(x)) + \\Big(1 - \\sum_k w_k(x)\\Big)\\, \\bar I

with ``Ī`` the channel's mean: weights that sum to 1 (a convex blend) ignore
the mean; patchwork's variance-preserving blend (Harrison's eq. 2, whose
weights sum to more than 1) takes the rest from it, as the synthesis does.
"""

from __future__ import annotations

import numpy as np

from ._validate import as_array, check_memory

__all__ = ["apply_coordinates"]

# slots whose weights are below this share of a pixel's largest are dropped when a method compacts its map
_NEGLIGIBLE = 0.0


def check_map(coordinates, weights):
    """The map as ``(H, W, K, 2)`` intp coordinates and ``(H, W, K)`` weights (None for copies).

    The checks of :func:`apply_coordinates` (and :func:`texsynth.io.save_coordinates`): a ValueError or
    TypeError naming what is wrong with ``coordinates`` or ``weights``.
    """
    coords = as_array(coordinates, "coordinates")
    if coords.ndim not in (3, 4) or coords.shape[-1] != 2:
        raise ValueError(
            f"coordinates must have shape (H, W, 2) (one exemplar pixel per output pixel) or (H, W, K, 2) with "
            f"weights (H, W, K), got shape {coords.shape}; pass info.coordinates of a synthesis (or the info itself)"
        )
    if not np.issubdtype(coords.dtype, np.integer):
        raise TypeError(
            f"coordinates must be integers (exemplar rows and columns), got dtype {coords.dtype}; pass "
            "info.coordinates, or np.rint(c).astype(int) for a map you made yourself"
        )
    if min(coords.shape[:-1]) == 0:
        raise ValueError(f"coordinates is empty (shape {coords.shape}); pass a map of at least one pixel")
    if weights is None:
        if coords.ndim == 4:
            raise ValueError(
                f"coordinates has shape {coords.shape} (H, W, K, 2): K sources per pixel need weights of shape "
                f"{coords.shape[:3]}; pass weights=info.weights (or the info itself)"
            )
        return coords[:, :, None, :], None
    w = as_array(weights, "weights")
    if coords.ndim == 3:
        coords = coords[:, :, None, :]
        if w.ndim == 2:
            w = w[..., None]
    if w.shape != coords.shape[:3]:
        raise ValueError(
            f"weights has shape {w.shape} but coordinates {coords.shape} need weights of shape {coords.shape[:3]}; "
            "pass the weights that came with the coordinates (info.weights)"
        )
    if not np.issubdtype(w.dtype, np.floating) and not np.issubdtype(w.dtype, np.integer):
        raise TypeError(f"weights must be real numbers, got dtype {w.dtype}")
    if not np.all(np.isfinite(w)):
        raise ValueError("weights contains NaN or infinite values; pass the weights that came with the coordinates")
    return coords, w


def _check_bounds(coords, shape, name):
    flat = coords.reshape(-1, 2)
    (lo_r, lo_c), (hi_r, hi_c) = flat.min(0).tolist(), flat.max(0).tolist()
    if lo_r < 0 or lo_c < 0 or hi_r >= shape[0] or hi_c >= shape[1]:
        hint = (" (-1 marks pixels that came from no exemplar pixel, e.g. efros_leung's given target pixels: "
                "render those from the target yourself)" if min(lo_r, lo_c) == -1 else "")
        raise ValueError(
            f"coordinates point outside {name}: rows {lo_r}..{hi_r} and columns {lo_c}..{hi_c}, but {name} is "
            f"{shape[0]}x{shape[1]}{hint}; pass channels of the size of the exemplar the map was made from"
        )


def _as_channel(image, name):
    arr = as_array(image, name)
    if arr.ndim not in (2, 3) or min(arr.shape) == 0:
        raise ValueError(f"{name} must have shape (H, W) or (H, W, C) like the exemplar, got shape {arr.shape}")
    kind = arr.dtype
    if kind == np.bool_ or not (np.issubdtype(kind, np.integer) or np.issubdtype(kind, np.floating)):
        raise TypeError(
            f"{name} has dtype {kind}; pass uint8, uint16 or float data (bool maps: .astype(np.uint8))"
        )
    return arr


def check_sources(source_index, coords):
    """The map's source index per slot, ``(H, W, K)`` int, or None (one exemplar); -1 is the average of
    the sources (a blend only). ``coords`` is the map as :func:`check_map` returns it."""
    if source_index is None:
        return None
    src = as_array(source_index, "source_index")
    if not np.issubdtype(src.dtype, np.integer):
        raise TypeError(f"source_index must be integers (the source of each slot), got dtype {src.dtype}; pass "
                        "info.source_index (or the info itself)")
    if coords.shape[2] == 1 and src.ndim == 2:
        src = src[..., None]
    if src.shape != coords.shape[:3]:
        raise ValueError(f"source_index has shape {src.shape} but coordinates {coords.shape} need one of shape "
                         f"{coords.shape[:3]}; pass the source_index that came with the coordinates")
    if src.min() < -1:
        raise ValueError(f"source_index has values below -1 (min {int(src.min())}); pass info.source_index")
    return src


def _split_channels(channels, several_sources):
    """``(keys, items)``: keys None for one channel, else list positions or dict keys; with several
    sources each item is that channel's list of images, one per source."""
    if isinstance(channels, dict):
        keys, items = list(channels), list(channels.values())
    elif isinstance(channels, (list, tuple)) and (not several_sources or (
            channels and isinstance(channels[0], (list, tuple)))):
        keys, items = list(range(len(channels))), list(channels)
    else:
        return None, [channels]
    if not items:
        raise ValueError("channels is an empty list; pass one image or a list of images of the exemplar's size")
    return keys, items


def _part_names(name, src):
    return [name] if src is None else [f"{name}[{i}]" for i in range(max(0, int(src.max())) + 1)]


def _as_parts(channel, name, src):
    """One channel as its list of images: the image itself, or (a map with sources) one per source."""
    if src is None:
        return [_as_channel(channel, name)]
    if not isinstance(channel, (list, tuple)):
        raise TypeError(f"{name} must be a list of images, one per source of the map (e.g. [height_a, "
                        f"height_b] for mix_textures([albedo_a, albedo_b], ...)), got {type(channel).__name__}")
    needed = max(0, int(src.max())) + 1
    if len(channel) < needed:
        raise ValueError(f"{name} has {len(channel)} image(s) but the map uses {needed} sources; pass one image "
                         "per source, in the order of the synthesis's sources")
    parts = [_as_channel(c, n) for c, n in zip(channel, _part_names(name, src))]
    for p, n in zip(parts[1:], _part_names(name, src)[1:]):
        if p.dtype != parts[0].dtype or p.shape[2:] != parts[0].shape[2:]:
            raise ValueError(f"{n} has dtype {p.dtype} and {p.shape[2:] or 'no'} channels but {name}[0] has "
                             f"{parts[0].dtype} and {parts[0].shape[2:] or 'no'}; convert the sources' images of "
                             "one channel to one layout")
    return parts


def _normal_flags(normals, keys):
    if isinstance(normals, (bool, np.bool_)):
        return dict.fromkeys(keys, bool(normals))
    if isinstance(normals, dict):
        unknown = set(normals) - set(keys)
        if unknown:
            raise ValueError(f"normals names channels {sorted(map(str, unknown))} that channels does not have; "
                             f"its keys are {list(keys)}")
        return {k: bool(normals.get(k, False)) for k in keys}
    try:
        flags = [bool(f) for f in normals]
    except TypeError:
        raise TypeError(f"normals must be a bool, one bool per channel or a dict of them, got "
                        f"{type(normals).__name__}") from None
    if len(flags) != len(keys):
        raise ValueError(f"normals has {len(flags)} flags for {len(keys)} channels; pass one per channel or one bool")
    return dict(zip(keys, flags))


def _white(kind):
    return float(np.iinfo(kind).max) if np.issubdtype(kind, np.integer) else 1.0


def _render(parts, flats, weights, blended, normal, name, average=False):
    """One channel (its image per source: one unless the map has sources) through the flat indices (one
    contiguous ``(H, W)`` array per slot, into the sources' pixels one after the other, then, with
    ``average``, into their average image) and the weights (None for copies; else a cache: slot 0
    dense, the others as (flat pixels, weights) where nonzero, converted once per working dtype)."""
    tables = [p.reshape(p.shape[0] * p.shape[1], -1) for p in parts]
    table = tables[0] if len(tables) == 1 else np.concatenate(tables)
    channel = parts[0]
    shape = flats[0].shape + channel.shape[2:]
    if normal and table.shape[1] < 3:
        raise ValueError(f"{name} is flagged as a normal map but has {table.shape[1]} channel(s); a normal map "
                         "has 3 (x, y, z encoded in [0, 1]), or 4 with alpha")
    if weights is None:  # copies: the values themselves, bit for bit, in their own dtype
        return np.take(table, flats[0], axis=0).reshape(shape)
    kind = channel.dtype
    work = np.float64 if kind == np.float64 or np.issubdtype(kind, np.signedinteger) else np.float32
    white = _white(kind)
    values = table.astype(work)  # the exemplar-sized table, decoded once (not the output-sized samples)
    if np.issubdtype(kind, np.integer):
        values *= work(1.0 / white)
    if normal:
        values = values * 2 - 1
    sampled = values  # the sources' pixels (and their average image, source -1)
    if average:
        sampled = np.concatenate([values, values.reshape(len(parts), -1, values.shape[-1]).mean(0)])
    key = np.dtype(work).name
    if key not in weights:  # slot 0 dense; the others only where they weigh (a few pixels of most maps)
        weights[key] = [weights["first"].astype(work)] + [(at, wk.astype(work)) for at, wk in weights["sparse"]]
    first, *others = weights[key]
    out = np.take(sampled, flats[0], axis=0)
    out *= first
    flat_out = out.reshape(-1, out.shape[-1])
    for (at, wk), flat in zip(others, flats[1:]):
        flat_out[at] += np.take(sampled, flat.reshape(-1)[at], axis=0) * wk
    if not weights["convex"]:  # weights not summing to 1 (patchwork): the rest from the mean
        out += (1.0 - weights["total"][..., None]).astype(work) * values.mean(0, dtype=np.float64).astype(work)
    if normal:  # renormalise where the pixel blends several sources, then encode in [0, 1]
        vec = out[..., :3]
        length = np.sqrt(np.einsum("...c,...c->...", vec, vec))[..., None]
        np.divide(vec, length, out=vec, where=blended[..., None] & (length > 0))
        out += 1
        out *= 0.5
    if np.issubdtype(kind, np.integer):
        info = np.iinfo(kind)
        out *= white
        np.rint(out, out=out)
        if not weights["convex"]:  # (a convex blend stays within the values it blends)
            np.clip(out, info.min, info.max, out=out)
        out = out.astype(kind)
    else:
        out = out.astype(kind, copy=False)
    return out.reshape(shape)


def apply_coordinates(channels, coordinates, weights=None, *, source_index=None, normals=False):
    """Render images of the exemplar's size through a synthesis's source-coordinate map.

    Examples
    --------
    >>> import texsynth
    >>> albedo = texsynth.data.load("bread")[:64, :64]
    >>> height = albedo.mean(-1)  # any image of the exemplar's size
    >>> out, info = texsynth.quilt(albedo, 96, block=24, rng=0, return_info=True)
    >>> texsynth.apply_coordinates([albedo, height], info)[1].shape
    (96, 96)

    One synthesis, a consistent set of channels: synthesise the albedo with
    ``return_info=True``, then render the normal, roughness and height maps
    of the same material through ``info``; every channel copies (or blends)
    the same exemplar pixels as the albedo did, so their edges line up.

    Parameters
    ----------
    channels : array_like, or a list, tuple or dict of them
        Images of the exemplar's height and width, ``(h, w)`` or ``(h, w,
        C)``, uint8, uint16 or float (any range: a height in metres is
        fine). Several at once share the index arithmetic.
    coordinates : array_like or info
        ``(H, W, 2)`` integer exemplar ``(row, col)`` per output pixel, or
        ``(H, W, K, 2)`` with ``weights`` (see the module's shape
        convention). An info of a synthesis (anything with a
        ``coordinates`` attribute) gives its ``coordinates`` and
        ``weights``.
    weights : array_like, optional
        ``(H, W, K)`` blend weights of the ``K`` sources (largest first), or
        None for copies. Taken from the info when ``coordinates`` is one.
    source_index : array_like of int, optional
        ``(H, W, K)``: which exemplar each slot's coordinates point into,
        for syntheses from several exemplars (:func:`texsynth.mix_textures`
        records ``info.source_index``; taken from the info when
        ``coordinates`` is one). Each channel is then a list of images, one per exemplar
        in the synthesis's order, each of its exemplar's size and all of
        one dtype and channel count: ``[height_a, height_b]``; several
        channels are a list of such lists or a dict of them. -1 reads the
        average of the channel's images (all of one size), in blend maps
        only.
        A video map (:func:`texsynth.patchwork_video`): coordinates ``(N,
        H, W, K, 2)`` with weights and source_index ``(N, H, W, K)``, the
        sources being the input frames (-1: their average, eq. 6's ``A``);
        each channel is the list of its images, one per input frame (all
        of them: the average is taken over the images given), and the
        result ``(N, H, W[, C])``.
    normals : bool, or a list or dict of bool
        Which channels are tangent-space normal maps (``x, y, z`` encoded in
        [0, 1], or 0..255 / 0..65535): their blended pixels are decoded to
        [-1, 1], blended, renormalised to unit length and encoded again.
        One bool for all channels, one per channel, or a dict by key.

    Returns
    -------
    numpy.ndarray, or a list, tuple or dict of them
        ``(H, W)`` or ``(H, W, C)`` per channel, each in its own dtype:
        uint16 stays uint16, float32 stays float32. Copied pixels are the
        channel's values bit for bit; blended integer pixels are rounded
        (and clipped to the type's range), blended float pixels are not
        clipped.

    Raises
    ------
    ValueError
        If the map has the wrong shape, points outside the channels (which
        must all have one height and width), or the weights or sources do
        not match it; if a channel flagged as normals has fewer than 3
        channels; if a channel has fewer images than the map has sources.
    TypeError
        For a non-integer map, a non-numeric channel, or a
        single image where a map with sources needs one per source.

    Notes
    -----
    Output pixel ``x`` with sources ``c_k(x)`` (in exemplar ``s_k(x)`` when
    the map has a ``source_index``; ``s_k = -1``: the average of the
    exemplars' images) and weights ``w_k(x)`` is
    ``O(x) = sum_k w_k(x) I(c_k(x)) + (1 - sum_k w_k(x)) mean(I)``: a plain
    copy when there is one source of weight 1, a convex blend when the
    weights sum to 1 (the mean term vanishes), and patchwork's
    variance-preserving eq. 2 otherwise. Rendering the exemplar itself
    reproduces the synthesis: exactly for copying methods, to rounding for
    blending ones (see each method's ``info.coordinates``). In the example
    above:

    >>> info.coordinates.shape
    (96, 96, 2)
    >>> bool(np.array_equal(texsynth.apply_coordinates(albedo, info), out))
    True

    A mixture of two materials renders each channel from both:

    >>> wood = texsynth.data.load("wood")[:48, :48]
    >>> mix, info = texsynth.mix_textures([albedo, wood], 32, neighborhood=texsynth.Neighborhood(levels=2), rng=0,
    ...                                   return_info=True)
    >>> info.coordinates.shape, info.source_index.shape
    ((32, 32, 2, 2), (32, 32, 2))
    >>> bool(np.allclose(texsynth.apply_coordinates([albedo, wood], info), mix))
    True

    A video texture renders a sequence, one image per input frame:

    >>> clip = np.stack([np.roll(albedo, 2 * t, axis=1) for t in range(4)])
    >>> video, info = texsynth.patchwork_video(clip, 32, 6, grid_spacing=16, rng=0, return_info=True)
    >>> texsynth.apply_coordinates(list(clip.mean(-1)), info).shape
    (6, 32, 32)

    ``benchmarks/bench_coordinates.py`` measures a 2048 x 2048 map applied
    to four channels against one fancy-indexing copy and
    ``scipy.ndimage.map_coordinates`` (``docs/benchmarks.md``).
    """
    if hasattr(coordinates, "coordinates"):  # an info of a synthesis
        info = coordinates
        if weights is None:
            weights = getattr(info, "weights", None)
        if source_index is None:
            source_index = getattr(info, "source_index", None)
        coordinates = info.coordinates
        if coordinates is None:
            raise ValueError(f"this {type(info).__name__} has no coordinates (coordinates is None); see its "
                             "docstring for the options that record them")
    frames = None
    if np.ndim(coordinates) == 5:  # a video map: the frames' maps stacked, rendered as one tall map
        coordinates, weights, source_index, frames = video_map(coordinates, weights, source_index)
    coords, w = check_map(coordinates, weights)
    src = check_sources(source_index, coords)
    average = src is not None and bool(np.any(src == -1))
    if average and w is None:
        raise ValueError("source_index has -1 (the average of the sources) in a map without weights; pass the "
                         "weights that came with it (info.weights)")
    keys, items = _split_channels(channels, src is not None)
    names = ["channels"] if keys is None else [f"channels[{k!r}]" for k in keys]
    parts = [_as_parts(c, n, src) for c, n in zip(items, names)]  # per channel, its image per source
    shapes = [p.shape[:2] for p in parts[0]]
    for channel, n in zip(parts[1:], names[1:]):
        for p, shape, part in zip(channel, shapes, _part_names(n, src)):
            if p.shape[:2] != shape:
                raise ValueError(f"{part} is {p.shape[0]}x{p.shape[1]} but {_part_names(names[0], src)[0]} is "
                                 f"{shape[0]}x{shape[1]}; every channel must have the size of its exemplar")
    flags = _normal_flags(normals, keys if keys is not None else [None])
    where = names[0] if keys is None else "the channels"
    if average and len(set(shapes)) > 1:
        raise ValueError(f"the map blends the average of the sources (source_index -1) but the images of {where} "
                         f"have different sizes {sorted(set(shapes))}; pass images of one size (the input frames)")
    if src is None:
        _check_bounds(coords, shapes[0], where)
    else:
        for i, shape in enumerate(shapes):
            if np.any(src == i):
                _check_bounds(coords[src == i], shape, f"source {i} of {where}")
        if average:
            _check_bounds(coords[src == -1], shapes[0], f"the average of {where}")
    out_pixels = float(coords.shape[0]) * coords.shape[1]
    check_memory(out_pixels * (8 * coords.shape[2] + sum(8 * (c[0].shape[2] if c[0].ndim == 3 else 1)
                                                         for c in parts)),
                 coords.shape[:2], "coordinates", "the rendered channels")
    # flat indices into the sources' pixels one after the other, one contiguous (H, W) array per slot,
    # computed once for all channels
    # (source -1, the average image, comes after the sources: the last start, the first's width)
    widths = np.array([shape[1] for shape in shapes] + [shapes[0][1]], np.intp)
    starts = np.concatenate([[0], np.cumsum([shape[0] * shape[1] for shape in shapes])]).astype(np.intp)
    slot = (lambda k: 0) if src is None else (lambda k: src[:, :, k])
    flats = [starts[slot(k)] + coords[:, :, k, 0].astype(np.intp) * widths[slot(k)] + coords[:, :, k, 1]
             for k in range(coords.shape[2])]
    blended = cache = None
    if w is not None:  # slot 0 dense; the others kept where they weigh (a few pixels of most maps)
        first = w[:, :, 0].astype(np.float64)
        total, blended = first.copy(), np.zeros(first.shape, bool)
        cache = {"first": first[..., None], "sparse": [], "convex": bool(w.min() >= 0)}
        for k in range(1, w.shape[2]):
            wk = np.ascontiguousarray(w[:, :, k], dtype=np.float64).reshape(-1)
            at = np.flatnonzero(wk)
            cache["sparse"].append((at, wk[at][:, None]))
            total.reshape(-1)[at] += wk[at]
            blended.reshape(-1)[at] = True
        cache["total"] = total
        cache["convex"] = cache["convex"] and bool(np.abs(total - 1).max() <= 1e-6)
    rendered = [_render(c, flats, cache, blended, flags[k], n, average)
                for c, n, k in zip(parts, names, keys if keys is not None else [None])]
    if frames is not None:
        rendered = [r.reshape((frames, -1) + r.shape[1:]) for r in rendered]
    if keys is None:
        return rendered[0]
    if isinstance(channels, dict):
        return dict(zip(keys, rendered))
    return type(channels)(rendered) if isinstance(channels, tuple) else rendered


def video_map(coordinates, weights, source_index):
    """A video map ``(N, H, W, K, 2)`` (weights and sources ``(N, H, W, K)``) as one ``(N * H, W, K, 2)``
    map, and ``N``: ``(coordinates, weights, source_index, N)``, to be checked by :func:`check_map`."""
    coords = as_array(coordinates, "coordinates")
    if coords.shape[-1] != 2 or weights is None or source_index is None:
        raise ValueError(
            f"coordinates of shape {coords.shape} (5 dimensions) is a video map (n_frames, H, W, K, 2), which needs "
            "weights and source_index of shape (n_frames, H, W, K); pass the info of patchwork_video(..., "
            "return_info=True) itself"
        )
    n = coords.shape[0]
    flat = (n * coords.shape[1],) + coords.shape[2:-1]
    for name, value in (("weights", weights), ("source_index", source_index)):
        if np.shape(value) != coords.shape[:-1]:
            raise ValueError(f"{name} has shape {np.shape(value)} but the video map {coords.shape} needs "
                             f"{coords.shape[:-1]}; pass the {name} that came with the coordinates")
    return (coords.reshape(flat + (2,)), np.reshape(weights, flat), np.reshape(source_index, flat), n)


# --------------------------------------------------------------------------
# helpers for the methods that record maps


def compact_slots(coordinates, weights, source_index=None):
    """Sort a blend map's slots by weight (largest magnitude first) and drop the slots no pixel uses.

    ``coordinates`` ``(H, W, K, 2)``, ``weights`` ``(H, W, K)`` and, for a
    map with sources, ``source_index`` ``(H, W, K)``; returns the same with
    ``K`` the largest number of nonzero weights at any pixel. Unused slots
    repeat the dominant slot's coordinates (and source) with weight 0, so
    ``coordinates[:, :, 0]`` is a valid copy map. (Weights are negative
    only in :func:`~texsynth.patchwork_video`'s eq. 6; the order of
    non-negative weights is the plain largest-first one.)
    """
    order = np.argsort(-np.abs(weights), axis=-1, kind="stable")
    weights = np.take_along_axis(weights, order, -1)
    coordinates = np.take_along_axis(coordinates, order[..., None], -2)
    used = np.abs(weights) > _NEGLIGIBLE
    k = max(1, int(np.count_nonzero(used, axis=-1).max()))
    weights, coordinates = np.ascontiguousarray(weights[..., :k]), np.ascontiguousarray(coordinates[..., :k, :])
    unused = ~used[..., :k]
    coordinates[unused] = np.broadcast_to(coordinates[:, :, :1], coordinates.shape)[unused]
    weights[unused] = 0
    if source_index is None:
        return coordinates, weights
    source_index = np.ascontiguousarray(np.take_along_axis(source_index, order, -1)[..., :k])
    source_index[unused] = np.broadcast_to(source_index[:, :, :1], source_index.shape)[unused]
    return coordinates, weights, source_index

