"""The checked inputs of an EM synthesis and their pyramids: exemplar, output, constraints, guides, fields.

:func:`prepare` checks the arrays once (as a :class:`Problem`); :func:`with_guides`, :func:`with_fields`
and :func:`with_margin` add guide channels, orientation and magnification fields and a margin; :func:`pyramids`
builds every level (Section 3.2 of Kwatra et al. 2005).
"""

from __future__ import annotations

import dataclasses
import numbers
from dataclasses import dataclass

import numpy as np

from .._validate import (as_float_array, as_image, as_size, check_memory, check_positive_float, check_positive_int,
                         with_channels)
from ..fields import as_field
from ..neighborhood import patches_within
from ..pyramid import gaussian_pyramid, level_shapes, max_levels
from ..search import is_auto

__all__ = ["Problem", "prepare", "with_guides", "with_fields", "with_margin", "free_inside", "pyramids", "level_sizes",
           "check_sizes", "check_mask", "check_like", "check_constraint_weight", "check_constraint_memory",
           "MAX_WEIGHT"]


# Largest weight of an energy term: far beyond any meaningful balance (the paper's mu is 10, a
# constraint of 100 is nearly hard), and below what overflows the float32 search features.
MAX_WEIGHT = 1e6


# Guides with at most this many distinct values (vectors) are label maps: histogram matching per label
_MAX_LABELS = 32


def check_sizes(neighborhood_sizes, name="neighborhood_sizes"):
    """Neighbourhood widths as a tuple of ints >= 2, largest first, each once; an int is one size.

    >>> check_sizes((8, 16, 8))
    (16, 8)
    """
    if isinstance(neighborhood_sizes, numbers.Integral) and not isinstance(neighborhood_sizes, bool):
        neighborhood_sizes = (neighborhood_sizes,)
    try:
        neighborhood_sizes = tuple(neighborhood_sizes)
    except TypeError:
        raise TypeError(f"{name} must be an int or a sequence of ints, got {neighborhood_sizes!r}") from None
    if not neighborhood_sizes:
        raise ValueError(f"{name} is empty; pass e.g. (32, 16, 8)")
    out = [check_positive_int(s, name, minimum=2) for s in neighborhood_sizes]
    return tuple(sorted(set(out), reverse=True))


def check_mask(mask, shape, name):
    """A ``(h, w)`` (or ``(h, w, 1)``) mask of bools or weights in [0, 1] of the spatial ``shape``, as float64."""
    arr = np.asarray(mask)
    if arr.ndim == 3 and arr.shape[-1] == 1:
        arr = arr[..., 0]
    if arr.ndim != 2 or arr.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} (one weight per pixel), got shape {np.shape(mask)}")
    return as_float_array(arr, name).astype(np.float64)


def check_like(image, shape, channels, name):
    arr, _ = with_channels(as_image(image, name))
    if arr.shape[:2] != tuple(shape) or arr.shape[-1] != channels:
        want = tuple(shape) + ((channels,) if channels > 1 else ())
        raise ValueError(f"{name} must have the output's shape {want} (channels as the exemplar), got shape "
                         f"{np.shape(image)}")
    return arr


def level_sizes(neighborhood_sizes, exemplar_shapes, output_shapes):
    """Neighbourhood sizes per level (Section 3.2): only those that fit the sub-sampled exemplar.

    At full resolution a size fits if the exemplar holds at least one
    neighbourhood; at sub-sampled levels it must hold a real choice of them,
    so the exemplar must be at least twice the neighbourhood size.
    """
    plan = []
    for level, (es, os_) in enumerate(zip(exemplar_shapes, output_shapes)):
        room = min(es) if level == 0 else min(es) // 2
        plan.append(tuple(s for s in neighborhood_sizes if s <= room and s <= min(os_)))
    return plan


@dataclass
class Problem:
    """The checked inputs of one synthesis: exemplar, output, constraints."""

    ex: np.ndarray  # (h, w, C) float
    grey: bool  # the exemplar had no channel axis
    shape: tuple  # output (H, W)
    sizes: tuple  # neighbourhood widths, largest first
    levels: int
    valid: np.ndarray  # (h, w) 1 where exemplar pixels may be copied
    constraint: tuple | None = None  # (mask, target, lambda) of eq. 2
    x_init: np.ndarray | None = None
    # (H, W, G) output guide, scaled; ex then holds the exemplar guide's G last channels
    guide: np.ndarray | None = None
    fields: tuple | None = None  # (theta, magnification), (H, W) each: the orientation and magnification fields
    labels: np.ndarray | None = None  # (L, G) label vectors (scaled) when the guides are label maps


def free_inside(problem):
    """Hard constraints whose free pixels all lie at least the largest neighbourhood inside the output: the
    canvas needs no margin, as no neighbourhood of a free pixel meets an edge of the output."""
    if problem.constraint is None or not np.isinf(problem.constraint[2]):
        return False
    reach = problem.sizes[0]
    free = problem.constraint[0] < 1 - 1e-6
    return not (free[:reach].any() or free[-reach:].any() or free[:, :reach].any() or free[:, -reach:].any())


def with_margin(problem, margin):
    """The problem on a canvas ``margin`` pixels larger (the output is its top-left part); constraints and
    the initial image extended by their edge values, the margin unconstrained."""
    pad = ((0, margin), (0, margin))
    constraint = problem.constraint
    if constraint is not None:
        m, t, lam = constraint
        constraint = (np.pad(m, pad), np.pad(t, pad + ((0, 0),), mode="edge"), lam)
    x_init = None if problem.x_init is None else np.pad(problem.x_init, pad + ((0, 0),), mode="edge")
    guide = None if problem.guide is None else np.pad(problem.guide, pad + ((0, 0),), mode="edge")
    fields = None if problem.fields is None else tuple(np.pad(f, pad, mode="edge") for f in problem.fields)
    shape = (problem.shape[0] + margin, problem.shape[1] + margin)
    return dataclasses.replace(problem, shape=shape, constraint=constraint, x_init=x_init, guide=guide, fields=fields)


def check_constraint_memory(problem):
    """Refuse soft constraints whose M-step (Algorithm 2) cannot fit: it queries an index of every
    exemplar neighbourhood of the largest size at the finest level, as float32 vectors (the image
    itself, when it is its own exemplar, at 512^2 and 64-px neighbourhoods: 9 GiB)."""
    if problem.constraint is None or not np.isfinite(problem.constraint[2]):
        return
    h, w, channels = problem.ex.shape
    size = max(problem.sizes)
    need = 3.0 * max(h - size + 1, 1) * max(w - size + 1, 1) * size * size * channels * 4
    try:
        check_memory(need, problem.ex.shape[:2], "exemplar", "the search index of the soft constraints (Algorithm 2)",
                     also={"neighborhood_sizes": problem.sizes})
    except ValueError as error:
        raise ValueError(f"{error}, or constraint_weight=float('inf') (hard constraints: the plain M-step, "
                         f"PatchMatch on large stages; texsynth.inpaint does this)") from None


def check_constraint_weight(constraint_weight):
    """λ of eq. 2: a number in [0, 1e6], or infinity for hard constraints."""
    if isinstance(constraint_weight, numbers.Real) and not isinstance(constraint_weight, bool) \
            and constraint_weight == np.inf:
        return np.inf
    return check_positive_float(constraint_weight, "constraint_weight", allow_zero=True, maximum=MAX_WEIGHT)


def prepare(exemplar, size, neighborhood_sizes, levels, *, constraint_weight=1.0, mask=None, target=None,
            exemplar_mask=None, init=None, sizes_name="neighborhood_sizes", auto_schedule=None):
    """The arrays of an EM synthesis, checked, as a :class:`Problem`.

    ``"auto"`` sizes or levels are resolved by ``schedule(exemplar, shape) -> (sizes, levels)`` (the method's
    preset; None: Kwatra et al.'s ``(32, 16, 8)`` over 3 levels).
    """
    ex = as_image(exemplar, "exemplar")
    ex, grey = with_channels(ex)
    shape = as_size(size)
    if is_auto(neighborhood_sizes) or is_auto(levels):
        auto_sizes, auto_levels = ((32, 16, 8), 3) if auto_schedule is None else auto_schedule(ex, shape)
        neighborhood_sizes = auto_sizes if is_auto(neighborhood_sizes) else neighborhood_sizes
        levels = auto_levels if is_auto(levels) else levels
    sizes = check_sizes(neighborhood_sizes, sizes_name)
    levels = check_positive_int(levels, "levels")
    lam = check_constraint_weight(constraint_weight)
    smallest = sizes[-1]
    if smallest > min(ex.shape[:2]):
        raise ValueError(
            f"exemplar is {ex.shape[0]}x{ex.shape[1]} but the smallest neighborhood is {smallest}x{smallest}; "
            f"pass {sizes_name} no larger than {min(ex.shape[:2])} or a larger exemplar"
        )
    if smallest > min(shape):
        raise ValueError(
            f"size {shape} is smaller than the smallest neighborhood {smallest}x{smallest}; "
            f"pass a larger size or smaller {sizes_name}"
        )
    valid = np.ones(ex.shape[:2])
    if exemplar_mask is not None:
        valid = check_mask(exemplar_mask, ex.shape[:2], "exemplar_mask")
        valid = (valid > 0.5).astype(np.float64)
        free = patches_within(valid > 0.5, smallest)
        if not free.any():
            raise ValueError(
                f"exemplar_mask leaves no {smallest}x{smallest} neighborhood of the exemplar free of masked pixels; "
                "mark more pixels valid or pass smaller neighborhood_sizes"
            )
    channels = ex.shape[-1]
    constraint = None
    if mask is not None and target is None:
        raise ValueError("mask was given without target; pass target=image holding the wanted values at the masked "
                         "pixels")
    if target is not None:
        t = check_like(target, shape, channels, "target")
        m = np.ones(shape) if mask is None else check_mask(mask, shape, "mask")
        constraint = (m, t.astype(ex.dtype), lam)
    x_init = None if init is None else check_like(init, shape, channels, "init").astype(ex.dtype)
    return Problem(ex, grey, shape, sizes, levels, valid, constraint, x_init)


def _check_guide(guide, shape, name):
    """A guide ``(h, w)`` or ``(h, w, G)`` in [0, 1] of the spatial ``shape``, as ``(h, w, G)`` float."""
    if isinstance(guide, (str, bytes, dict, numbers.Number)):
        raise TypeError(f"{name} must be an array of shape {tuple(shape)} or {tuple(shape) + ('G',)} "
                        f"(guide channels in [0, 1]), got {guide!r}")
    arr = as_float_array(guide, name)
    if arr.ndim == 2:
        arr = arr[..., None]
    if arr.ndim != 3 or arr.shape[:2] != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)} or {tuple(shape) + ('G',)} (one label or guide "
                         f"value per pixel), got shape {np.shape(guide)}")
    return arr


def with_guides(problem, exemplar_guide, output_guide, guide_weight):
    """Guided synthesis (image analogies' texture by numbers): the guides as extra channels.

    The exemplar guide is appended to the exemplar and the output guide kept for the output, both
    multiplied by ``sqrt(guide_weight)`` (the colours' [0, 1] units), so every neighbourhood distance
    compares the guides too; constraint targets and the initial image get the output guide's channels.
    """
    weight = check_positive_float(guide_weight, "guide_weight", allow_zero=True, maximum=MAX_WEIGHT)
    if exemplar_guide is None and output_guide is None:
        return problem
    if exemplar_guide is None or output_guide is None:
        given, missing = ("exemplar_guide", "output_guide") if output_guide is None else ("output_guide",
                                                                                          "exemplar_guide")
        raise ValueError(f"{given} was given without {missing}; pass both (the exemplar's label map and the "
                         f"output's) or neither")
    ge = _check_guide(exemplar_guide, problem.ex.shape[:2], "exemplar_guide")
    go = _check_guide(output_guide, problem.shape, "output_guide")
    if ge.shape[-1] != go.shape[-1]:
        raise ValueError(f"exemplar_guide has {ge.shape[-1]} channel(s) but output_guide has {go.shape[-1]}; "
                         f"pass guides with the same channels (the same labels in both)")
    if weight == 0:  # guides of no weight: the unguided synthesis, bit for bit
        return problem
    dtype = problem.ex.dtype
    s = np.sqrt(weight)
    labels = np.unique(ge.reshape(-1, ge.shape[-1]), axis=0)
    used = np.unique(go.reshape(-1, go.shape[-1]), axis=0)
    if len(labels) > _MAX_LABELS or len(used) > _MAX_LABELS or not all((labels == u).all(-1).any() for u in used):
        labels = None  # continuous guides (or output values the exemplar lacks): one histogram for all
    else:
        labels = (labels * s).astype(dtype)
    ge, go = (ge * s).astype(dtype), (go * s).astype(dtype)
    ex = np.concatenate([problem.ex, ge], axis=-1)
    constraint = problem.constraint
    if constraint is not None:
        m, t, lam = constraint
        constraint = (m, np.concatenate([t, go], axis=-1), lam)
    x_init = None if problem.x_init is None else np.concatenate([problem.x_init, go], axis=-1)
    return dataclasses.replace(problem, ex=ex, constraint=constraint, x_init=x_init, guide=go, labels=labels)


def with_fields(problem, orientation, magnification):
    """The orientation and magnification fields (Zhang et al. 2003's local frames) over the output, checked."""
    theta = as_field(orientation, problem.shape, "orientation")
    factor = as_field(magnification, problem.shape, "magnification", positive=True)
    if theta is None and factor is None:
        return problem
    if problem.constraint is not None and np.isfinite(problem.constraint[2]):
        raise ValueError("orientation and magnification fields do not combine with soft constraints (target with a "
                         "finite constraint_weight: Algorithm 2 ranks plain neighbourhoods); pass "
                         "constraint_weight=float('inf') (hard constraints) or no fields")
    theta = np.zeros(problem.shape) if theta is None else theta
    factor = np.ones(problem.shape) if factor is None else factor
    return dataclasses.replace(problem, fields=(theta, factor))


def pyramids(exemplar, valid, shape, levels, constraint, init, wrap):
    """Exemplar, its valid mask, output shapes, constraints and init at every level."""
    levels = max(1, min(levels, max_levels(exemplar.shape[:2]), max_levels(shape)))
    pmode = "wrap" if wrap else "reflect"
    ex_pyr = gaussian_pyramid(exemplar, levels)
    # a coarse exemplar pixel is valid only if no masked pixel contributed to it
    valid_pyr = [v > 1 - 1e-6 for v in gaussian_pyramid(valid, levels)]
    out_shapes = level_shapes(shape, levels)
    cons_pyr = [constraint] + [None] * (levels - 1)
    if constraint is not None:
        m, t, lam = constraint
        mp = gaussian_pyramid(m, levels, mode=pmode)
        mtp = gaussian_pyramid(m[..., None] * t, levels, mode=pmode)
        for lv in range(1, levels):
            # target of a coarse pixel: the mask-weighted average of the fine targets
            tl = np.divide(mtp[lv], mp[lv][..., None], out=np.zeros_like(mtp[lv]), where=mp[lv][..., None] > 1e-12)
            cons_pyr[lv] = (mp[lv], tl.astype(exemplar.dtype), lam)
    init_pyr = None if init is None else gaussian_pyramid(init, levels, mode=pmode)
    return ex_pyr, valid_pyr, out_shapes, cons_pyr, init_pyr
