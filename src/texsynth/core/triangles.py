"""Triangles in 3-D: the closest point of a triangle to a point, shared by the surface and geometry families.

Examples
--------
>>> import numpy as np
>>> from texsynth.core.triangles import closest_on_triangles
>>> a, b, c = np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0])
>>> point, bary = closest_on_triangles(np.array([0.25, 0.25, 2.0]), a, b, c)
>>> point.tolist(), bary.tolist()
([0.25, 0.25, 0.0], [0.5, 0.25, 0.25])
"""

from __future__ import annotations

import numpy as np

__all__ = ["closest_on_triangles"]


def closest_on_triangles(points, corner_a, corner_b, corner_c):
    """Closest points of triangles ``abc`` to points ``p``, and their barycentric coordinates.

    Ericson's region test (*Real-Time Collision Detection*, 2005, Section 5.1.5), vectorised: the
    point's projection when it falls inside the triangle, else the nearest point of the vertex or
    edge region it falls in. Degenerate (zero-area) triangles give their nearest edge or vertex.

    Parameters
    ----------
    points, corner_a, corner_b, corner_c : numpy.ndarray
        ``(..., 3)`` points and the triangles' corners, broadcast together.

    Returns
    -------
    point : numpy.ndarray
        ``(..., 3)`` the closest points.
    bary : numpy.ndarray
        ``(..., 3)`` their weights of the three corners (non-negative, summing to 1).
    """
    p, a, b, c = points, corner_a, corner_b, corner_c
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("...i,...i", ab, ap), np.einsum("...i,...i", ac, ap)
    bp, cp = p - b, p - c
    d3, d4 = np.einsum("...i,...i", ab, bp), np.einsum("...i,...i", ac, bp)
    d5, d6 = np.einsum("...i,...i", ab, cp), np.einsum("...i,...i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = 1.0 / (va + vb + vc)
        bary = np.stack(np.broadcast_arrays(1 - (vb + vc) * denom, vb * denom, vc * denom), -1)  # inside
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    one, zero = np.ones_like(d1), np.zeros_like(d1)
    cases = [  # (condition, barycentrics) in Ericson's order: the first that holds wins (applied in reverse)
        ((d1 <= 0) & (d2 <= 0), (one, zero, zero)),
        ((d3 >= 0) & (d4 <= d3), (zero, one, zero)),
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), (1 - t_ab, t_ab, zero)),
        ((d6 >= 0) & (d5 <= d6), (zero, zero, one)),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), (1 - t_ac, zero, t_ac)),
        ((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), (zero, 1 - t_bc, t_bc)),
    ]
    for condition, weights in reversed(cases):
        bary = np.where(condition[..., None], np.stack(np.broadcast_arrays(*weights), -1), bary)
    point = bary[..., :1] * a + bary[..., 1:2] * b + bary[..., 2:] * c
    return point, bary
