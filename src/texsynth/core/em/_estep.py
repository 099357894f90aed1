"""The E-step: the image that minimises the weighted patch energy for fixed matches.

``x <- argmin_x sum_p ω_p ρ_p(x) + λ E_c(x)`` (Kwatra et al. 2005, eqs. 1-2): a weighted average of the
matched neighbourhoods (and the constraint targets), or, with the gradient term, the Poisson-like linear
system of Section 3 solved by preconditioned conjugate gradients (:func:`solve_gradient_system`).
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sfft

from .._parallel import parallel_for
from .._validate import max_threads
from ..neighborhood import PatchSum
from ._patches import BLOCK_VALUES, difference_weights
from ._terms import match_channel

__all__ = ["e_step", "Average", "solve_gradient_system", "grid_parts"]


# Conjugate gradients of the gradient-energy E-step: relative residual and cap.
_CG_RTOL = 1e-10


_CG_MAXITER = 500


def _dx(u, wrap):
    return np.roll(u, -1, axis=1) - u if wrap else u[:, 1:] - u[:, :-1]


def _dy(u, wrap):
    return np.roll(u, -1, axis=0) - u if wrap else u[1:] - u[:-1]


def _dxT(e, wrap, shape):
    if wrap:
        return np.roll(e, 1, axis=1) - e
    out = np.zeros(shape + e.shape[2:], dtype=e.dtype)
    out[:, :-1] -= e
    out[:, 1:] += e
    return out


def _dyT(e, wrap, shape):
    if wrap:
        return np.roll(e, 1, axis=0) - e
    out = np.zeros(shape + e.shape[2:], dtype=e.dtype)
    out[:-1] -= e
    out[1:] += e
    return out


def _laplacian_eigenvalues(n, wrap):
    """Eigenvalues of D^T D on a line of n pixels: periodic (FFT) or Neumann (DCT-II)."""
    k = np.arange(n)
    return 2.0 - 2.0 * np.cos((2.0 if wrap else 1.0) * np.pi * k / n)


def solve_gradient_system(data_w, rhs_data, wx, gx, wy, gy, gradient_weight, wrap, previous, stats=None):
    """Minimise sum_i a_i (x_i - m_i)^2 + μ sum_e b_e (D x - G)_e^2 over x.

    Normal equations ``(A + μ Dᵀ B D) x = A m + μ Dᵀ B G`` (the "Poisson-like
    linear system" of the paper, with spatially varying weights), solved by
    preconditioned conjugate gradients. The weights vary over 4-6 orders of
    magnitude (IRLS weights of matched and unmatched neighbourhoods), so the
    preconditioner first scales the system by its diagonal ``d``
    (``S = diag(sqrt(d))``; ``S⁻¹ K S⁻¹`` has a unit diagonal) and then
    inverts the constant-coefficient operator with the scaled system's mean
    coefficients, which the FFT (periodic output) or the DCT (non-periodic
    output, Neumann boundary) diagonalises exactly:
    ``P⁻¹ = S⁻¹ C⁻¹ S⁻¹``. Measured on the systems of a 3-level synthesis
    (64-256 px, μ = 10): 15-30 iterations to a relative residual of 1e-10,
    against 85-500 (and the 500-iteration cap at up to 4e-8) with the
    unscaled constant-coefficient preconditioner. ``stats``, a dict, receives ``iterations`` and ``residual``.
    """
    shape = data_w.shape
    a = data_w[..., None]
    bx, by = wx[..., None], wy[..., None]

    def apply(u):
        return a * u + gradient_weight * (_dxT(bx * _dx(u, wrap), wrap, shape) + _dyT(by * _dy(u, wrap), wrap, shape))

    b = rhs_data + gradient_weight * (_dxT(bx * gx, wrap, shape) + _dyT(by * gy, wrap, shape))
    # diagonal of the operator: a_i + μ (weights of the differences that touch pixel i)
    edges = np.zeros(shape)
    if wrap:
        edges += wx + np.roll(wx, 1, axis=1) + wy + np.roll(wy, 1, axis=0)
    else:
        edges[:, :-1] += wx
        edges[:, 1:] += wx
        edges[:-1] += wy
        edges[1:] += wy
    d = np.maximum(data_w + gradient_weight * edges, 1e-300)
    sd = np.sqrt(d)
    if wrap:
        bxs, bys = wx / (sd * np.roll(sd, -1, axis=1)), wy / (sd * np.roll(sd, -1, axis=0))
    else:
        bxs, bys = wx / (sd[:, :-1] * sd[:, 1:]), wy / (sd[:-1] * sd[1:])
    lam = (
        float((data_w / d).mean())
        + gradient_weight * float(bys.mean()) * _laplacian_eigenvalues(shape[0], wrap)[:, None]
        + gradient_weight * float(bxs.mean()) * _laplacian_eigenvalues(shape[1], wrap)[None, :]
    )[..., None]
    lam = np.maximum(lam, 1e-300)
    sd = sd[..., None]

    def precondition(r):
        r = r / sd
        if wrap:
            z = np.real(sfft.ifft2(sfft.fft2(r, axes=(0, 1)) / lam, axes=(0, 1)))
        else:
            z = sfft.idctn(sfft.dctn(r, type=2, axes=(0, 1), norm="ortho") / lam, type=2, axes=(0, 1), norm="ortho")
        return z / sd

    x = previous.copy()
    r = b - apply(x)
    z = precondition(r)
    p = z.copy()
    rz = np.einsum("ijc,ijc->c", r, z)
    bnorm = np.sqrt(np.einsum("ijc,ijc->c", b, b))
    iterations = 0
    for iterations in range(_CG_MAXITER + 1):
        if np.all(np.sqrt(np.einsum("ijc,ijc->c", r, r)) <= _CG_RTOL * np.maximum(bnorm, 1e-300)):
            break
        if iterations == _CG_MAXITER:
            break
        q = apply(p)
        pq = np.einsum("ijc,ijc->c", p, q)
        alpha = np.divide(rz, pq, out=np.zeros_like(rz), where=pq > 0)
        x += alpha * p
        r -= alpha * q
        z = precondition(r)
        rz_new = np.einsum("ijc,ijc->c", r, z)
        beta = np.divide(rz_new, rz, out=np.zeros_like(rz), where=rz > 0)
        p = z + beta * p
        rz = rz_new
    if stats is not None:
        stats["iterations"] = iterations
        stats["residual"] = float(np.max(np.sqrt(np.einsum("ijc,ijc->c", r, r)) / np.maximum(bnorm, 1e-300)))
    return x


def grid_parts(centers, budget):
    """Slices of ``centers`` (a row-major grid, or a part of one) holding about ``budget`` centres each, in
    whole rows of the grid when ``centers`` is all of it."""
    ncols = int(np.count_nonzero(centers[:, 0] == centers[0, 0]))
    step = ncols * max(1, budget // ncols)
    return [slice(a, a + step) for a in range(0, len(centers), step)]


def e_step(exemplar, matches, centers, shape, patch_weights, mode, gradient_weight, constraint, previous,
           pixel_weights=None, votes=None, warp=None):
    """x <- argmin_x sum_p ω_p ρ_p(x) + λ E_c(x): eq. 1 (and eq. 2) minimised over x.

    The ``z_p`` of the grid ``centers`` are added a few grid rows at a time
    (memory grows with the output, not with the overlap); ``votes``
    ``(indices, centres, weights)`` are more neighbourhoods averaged in (the
    completeness term's ``q_j`` at ``p(j)``). With a :class:`WarpedPatches` (fields,
    ``μ = 0``) every ``z_p`` is splatted at its rotated, scaled positions.
    Pixels that no neighbourhood reaches (a warp's gaps; under hard
    constraints, the pixels away from the unconstrained ones,
    :func:`touching_free`) keep their value in ``previous``.
    """
    pixel_weights = exemplar.g if pixel_weights is None else pixel_weights
    w, channels = exemplar.size, exemplar.image.shape[-1]
    wrap = mode == "wrap"
    h_, w_ = shape
    gxw, gyw = difference_weights(pixel_weights)
    shift = w // 2 - (w - 1) // 2  # centre of a (w-1)-wide difference patch, anchored at its left pixel
    values = PatchSum(shape, channels, mode=mode) if warp is None else [np.zeros(tuple(shape) + (channels,)),
                                                                        np.zeros(tuple(shape))]
    if gradient_weight > 0:  # gradient energy: accumulate the patches' differences like the patches themselves
        dx = PatchSum((h_, w_ if wrap else w_ - 1), channels, mode=mode)
        dy = PatchSum((h_ if wrap else h_ - 1, w_), channels, mode=mode)
    budget = BLOCK_VALUES // (w * w * channels)
    parts = [(matches[p], centers[p], patch_weights[p]) for p in grid_parts(centers, budget)]
    for zi, at, om in parts + ([] if votes is None else [votes]):
        z = exemplar.patches(zi)
        if warp is not None:
            warp.add(values, z, at, om, pixel_weights)
            continue
        values.add(z, at, patch_weights=om, pixel_weights=pixel_weights)
        if gradient_weight > 0:
            dx.add(z[:, :, 1:] - z[:, :, :-1], at - [0, shift], patch_weights=om, pixel_weights=gxw)
            dy.add(z[:, 1:] - z[:, :-1], at - [shift, 0], patch_weights=om, pixel_weights=gyw)
    if warp is None:
        mean, wd = values.average()
        data_w = wd.copy()
        rhs = wd[..., None] * mean
    else:  # the splatted sums
        rhs, data_w = values
    uncovered = data_w <= 0  # a pixel no neighbourhood reaches keeps its value (weight 1 on x0)
    if uncovered.any():
        rhs[uncovered] = previous[uncovered]
        data_w[uncovered] = 1.0
    hard = constraint is not None and np.isinf(constraint[2])
    if constraint is not None and not hard:  # eq. 2: the weighted average with the targets (Section 4)
        m, t, lam = constraint
        data_w += lam * m
        rhs += (lam * m)[..., None] * t
    if gradient_weight == 0:
        x = rhs / data_w[..., None]
    else:
        (gx, wx), (gy, wy) = dx.average(), dy.average()
        x = solve_gradient_system(data_w, rhs, wx, gx, wy, gy, gradient_weight, wrap, previous.astype(np.float64))
    if hard:  # λ = ∞: the targets replace the average where the mask is 1 (blended where a coarse pixel is partly
        # known)
        m, t, _ = constraint
        x = (1 - m)[..., None] * x + m[..., None] * t
    return x.astype(exemplar.image.dtype, copy=False)


class Average:
    """The E-step of one stage with every term that votes in it: ``average(state, omega, iteration) -> x``.

    The matches ``z_p`` at ``centers`` are averaged with their IRLS weights (times each neighbourhood's
    ``confidence``, Wexler et al. 2007) by :func:`e_step`; the :class:`Completeness` votes ``q_j`` at
    ``p(j)`` join them (Simakov et al. 2008's update rule), except those of an offset the
    :class:`Occurrence` copy limit already exceeds; then the colour histograms are restored
    (``histograms``, :func:`histogram_groups`) and the guide channels reset to the output's ``guide``.

    Parameters
    ----------
    exemplar : ExemplarPatches
        The exemplar's neighbourhoods of the stage's size (their ``mu``: the gradient term's weight).
    centers : numpy.ndarray
        ``(N, 2)`` the grid ``X†`` of the stage.
    shape : tuple of int
        The output's ``(H, W)``.
    mode : {"valid", "wrap"}
    constraint : tuple or None
        ``(mask, target, λ)`` of eq. 2 (``λ = inf``: hard constraints).
    x : numpy.ndarray or None
        The image the stage starts from (its pixels that no neighbourhood reaches stay); None: zeros.
    warp : WarpedPatches or None
    confidence : numpy.ndarray or None
        ``(N,)`` weights of the neighbourhoods (:func:`confidence_weights`).
    completeness : Completeness or None
    occurrence : Occurrence or None
    histograms : list
        ``(where, targets)`` pairs of :func:`histogram_groups`.
    guide : numpy.ndarray or None
        ``(H, W, G)`` the output guide: the last ``G`` channels.
    first_falloff, falloff : numpy.ndarray or None
        The pixel weights of the first E-step (a bootstrap from random neighbourhoods) and of the others
        (None: the exemplar's fall-off).

    Examples
    --------
    See ``docs/architecture.md`` ("Add an EM method").
    """

    def __init__(self, exemplar, centers, shape, mode, *, constraint=None, x=None, warp=None, confidence=None,
                 completeness=None, occurrence=None, histograms=(), guide=None, first_falloff=None, falloff=None):
        self.ex, self.centers, self.shape, self.mode = exemplar, centers, tuple(shape), mode
        self.constraint, self.warp, self.confidence = constraint, warp, confidence
        self.completeness, self.occurrence, self.histograms, self.guide = completeness, occurrence, histograms, guide
        self.first_falloff, self.falloff = first_falloff, falloff
        self.current = x if x is not None else np.zeros(self.shape + (exemplar.image.shape[-1],), exemplar.image.dtype)
        self.threads = max_threads() if histograms else 1  # the channels at once (sorting releases the GIL)

    def __call__(self, state, omega, iteration):
        exemplar, n = self.ex, len(self.centers)
        zidx, pj = state
        omega = np.ones(n) if omega is None else omega
        votes = None
        if pj is not None:  # the completeness votes: q_j averaged at its centre p(j)
            vote_w = self.completeness.scale * omega[n:]
            if self.occurrence is not None and self.occurrence.offsets is not None:
                # no vote for an offset already copied beyond the copy limit
                vote_w = vote_w * (self.occurrence.copy_penalty(exemplar, self.completeness.jidx, pj) == 0)
            votes = (self.completeness.jidx, pj, vote_w)
        g = self.first_falloff if iteration == 0 and self.first_falloff is not None else self.falloff
        weights = omega[:n] if self.confidence is None else omega[:n] * self.confidence
        current = e_step(exemplar, zidx, self.centers, self.shape, weights, self.mode, exemplar.mu, self.constraint,
                         self.current, pixel_weights=g, votes=votes, warp=self.warp)
        for where, targets in self.histograms:  # the exemplar's colour histograms, against the E-step's wash-out
            parallel_for(lambda c: match_channel(current, c, where, targets[c]), len(targets), self.threads)
        if self.guide is not None:  # the output's guide channels are given: reset after every E-step
            current[..., current.shape[-1] - self.guide.shape[-1]:] = self.guide
        self.current = current
        return current
