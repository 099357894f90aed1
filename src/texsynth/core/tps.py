"""Thin-plate splines in 2-D and TPS-RPM non-rigid point matching.

A thin-plate spline (TPS) [1]_ is the smoothest map of the plane that takes
a set of control points onto target points: it minimises the bending energy
(Duchon's semi-norm)

.. math:: J(f) = \\iint f_{xx}^2 + 2 f_{xy}^2 + f_{yy}^2 \\,dx\\,dy

among all maps through the targets (or, with a regularisation ``lambda > 0``,
it minimises ``sum_a w_a |y_a - f(x_a)|^2 + lambda * c^T Phi c``). Its closed
form is an affine map plus radial basis functions
``U(r) = r^2 log r`` centred at the control points:

.. math:: f(x) = d_0 + D x + \\sum_a c_a U(|x - x_a|),
          \\quad \\sum_a c_a = 0, \\; \\sum_a c_a x_a^T = 0.

TPS-RPM (Chui and Rangarajan 2000 [2]_) finds the correspondence between two
point sets *and* the TPS that aligns them at once: a soft-assignment matrix
``M`` with an outlier row and column, normalised by Sinkhorn's alternating
row/column scaling, is alternated with TPS fits while a temperature ``T`` is
lowered by deterministic annealing, so the assignment hardens gradually from
"everything matches everything" to one-to-one. Ruiters et al. 2010 [3]_
(Section 4.2) modify the last iteration: points left as outliers are
assigned to their own position, which keeps the final warp from stretching
towards distant, unrelated features.

Everything here is batched: arrays of point sets ``(..., K, 2)`` with
per-point weights (weight 0 = padding) are fitted and matched at once, which
is what patch interpolation needs (thousands of small point sets).

References
----------
.. [1] J. Duchon, "Splines minimizing rotation-invariant semi-norms in
   Sobolev spaces", Lecture Notes in Math. 571, 1977, pp. 85-100.
   :doi:`10.1007/BFb0086566`; F. L. Bookstein, "Principal warps: thin-plate
   splines and the decomposition of deformations", IEEE PAMI 11(6), 1989.
   :doi:`10.1109/34.24792`
.. [2] H. Chui and A. Rangarajan, "A new algorithm for non-rigid point
   matching", CVPR 2000, vol. 2, pp. 44-51. :doi:`10.1109/CVPR.2000.854733`
.. [3] R. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
   interpolation", Computer Graphics Forum 29(4) (EGSR 2010), 1421-1429.
   :doi:`10.1111/j.1467-8659.2010.01739.x`
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._validate import check_in_range, check_positive_float, check_positive_int, one_blas_thread

__all__ = ["ThinPlateSpline", "fit_tps", "tps_kernel", "TPSRPMResult", "tps_rpm"]


def tps_kernel(r2):
    """The TPS radial basis ``U(r) = r^2 log r`` from squared distances ``r^2``.

    ``U(0) = 0`` (its limit). Same kernel as
    ``scipy.interpolate.RBFInterpolator(kernel="thin_plate_spline")``.

    >>> tps_kernel(np.array([0.0, 1.0, np.e ** 2])).round(6).tolist()
    [0.0, 0.0, 7.389056]
    """
    r2 = np.asarray(r2, dtype=np.float64)
    # r^2 log r = r^2 log(r^2) / 2; log(1) = 0 where r = 0 (no masked copies: this runs on
    # millions of distances per TPS-RPM batch)
    out = np.log(np.where(r2 > 0, r2, 1.0))
    out *= r2
    out *= 0.5
    return out


def _sq_dist(a, b):
    """Squared distances between (..., n, 2) and (..., m, 2) -> (..., n, m)."""
    d = (a[..., :, None, 0] - b[..., None, :, 0]) ** 2
    d += (a[..., :, None, 1] - b[..., None, :, 1]) ** 2
    return d


def _affine_basis(points):
    """``P = [1, x, y]`` rows, shape (..., n, 3)."""
    ones = np.ones(points.shape[:-1] + (1,), dtype=np.float64)
    return np.concatenate([ones, points], axis=-1)


@dataclass(frozen=True)
class ThinPlateSpline:
    """A fitted thin-plate spline (or a batch of them); call it to warp points.

    Attributes
    ----------
    control_points : numpy.ndarray, shape (..., K, 2)
        The knots ``x_a``.
    coefficients : numpy.ndarray, shape (..., K, 2)
        The radial weights ``c_a`` (zero for points of weight 0).
    affine : numpy.ndarray, shape (..., 3, 2)
        The affine part: ``f_aff(x) = [1, x_0, x_1] @ affine``.
    """

    control_points: np.ndarray
    coefficients: np.ndarray
    affine: np.ndarray

    def __call__(self, points):
        """Warp ``points`` of shape ``(..., M, 2)`` (batch dims as the spline's)."""
        points = np.asarray(points, dtype=np.float64)
        if points.shape[-1] != 2:
            raise ValueError(f"points must have shape (..., M, 2), got {points.shape}")
        kernel = tps_kernel(_sq_dist(points, self.control_points))  # (..., M, K)
        return self.affine_part(points) + kernel @ self.coefficients

    def affine_part(self, points):
        """The affine component ``d_0 + D x`` alone at ``points`` (..., M, 2)."""
        points = np.asarray(points, dtype=np.float64)
        return _affine_basis(points) @ self.affine

    @property
    def bending_energy(self):
        """Duchon's bending energy ``J(f)`` summed over both output coordinates.

        Equals ``8 pi trace(c^T Phi c)`` for the kernel ``U = r^2 log r``
        (Wahba 1990, Section 2.4); zero exactly for affine maps.
        """
        phi = tps_kernel(_sq_dist(self.control_points, self.control_points))
        c = self.coefficients
        return 8.0 * np.pi * np.einsum("...ka,...kl,...la->...", c, phi, c)


class _TPSSystem:
    """Batched weighted smoothing-TPS solver for fixed control points.

    Solves ``[[Phi + lambda W^-1, P], [P^T, 0]] [c; d] = [y; 0]`` (the
    stationarity conditions of ``sum_a w_a |y_a - f(x_a)|^2 + lambda c^T Phi c``
    under ``P^T c = 0``). A point of weight 0 becomes a decoupled dummy row
    ``c_a = 0``. ``affine_regularization`` then re-fits the affine part given
    ``c`` with a ridge towards the identity, as Chui and Rangarajan's
    reference implementation does. The parts that depend only on the
    control points are built once (TPS-RPM refits hundreds of times).
    """

    def __init__(self, points, phi=None):
        self.k = points.shape[-2]
        self.phi = tps_kernel(_sq_dist(points, points)) if phi is None else phi
        self.p = _affine_basis(points)
        self.pt = np.swapaxes(self.p, -1, -2)
        self.ident = np.zeros((3, 2))
        self.ident[1:] = np.eye(2)
        self.singular = None  # which systems were singular at the last solve

    def solve(self, targets, weights, regularization, affine_regularization):
        k = self.k
        valid = weights > 0
        lam = np.asarray(regularization, dtype=np.float64)[..., None]
        inv_w = 1.0 / np.where(valid, weights, 1.0)
        vv = valid[..., :, None] & valid[..., None, :]
        p = self.p * valid[..., None]
        system = np.zeros(valid.shape[:-1] + (k + 3, k + 3))
        system[..., :k, :k] = np.where(vv, self.phi, 0.0)
        idx = np.arange(k)
        system[..., idx, idx] += np.where(valid, lam * inv_w, 1.0)  # dummy rows: c_a = 0
        system[..., :k, k:] = p
        system[..., k:, :k] = np.swapaxes(p, -1, -2)
        rhs = np.zeros(valid.shape[:-1] + (k + 3, 2))
        rhs[..., :k, :] = targets * valid[..., None]
        sol, self.singular = _solve_or_lstsq(system, rhs, self.singular)
        coef, affine = sol[..., :k, :], sol[..., k:, :]
        lam2 = np.asarray(affine_regularization, dtype=np.float64)
        if np.any(lam2 > 0):
            # d = argmin sum_a w_a |y_a - Phi_a c - P_a d|^2 + lambda2 |d - d_identity|^2
            pw = p * weights[..., None]
            normal = np.swapaxes(pw, -1, -2) @ p + lam2[..., None, None] * np.eye(3)
            resid = targets - self.phi @ coef
            rhs_d = np.swapaxes(pw, -1, -2) @ resid + lam2[..., None, None] * self.ident
            affine = np.linalg.solve(normal, rhs_d)
        return coef, affine


def _solve_or_lstsq(system, rhs, singular=None):
    """Batched ``solve(system, rhs)``; the singular systems of the batch get the least-squares solution.

    Degenerate control points (all on one line, common for the feature
    pixels of a straight mortar joint) make the TPS system singular. Only
    those are solved by minimum-norm least squares (the pseudo-inverse with
    ``lstsq``'s cut-off ``eps * max(M, N)``, batched), the others by LU as
    before; one Python-level ``lstsq`` per problem for the whole batch cost
    11 s of a 20 s TPS-RPM stage. ``singular`` (a boolean mask over the
    flattened batch) is a guess from an earlier solve with the same control
    points: they are tried by LU directly, and the split is recomputed if that
    fails. Returns ``(solution, singular)``.
    """
    n = system.shape[-1]
    flat_s, flat_r = system.reshape(-1, n, n), rhs.reshape(-1, n, rhs.shape[-1])
    if singular is None or not singular.any():
        try:
            return np.linalg.solve(system, rhs), np.zeros(len(flat_s), bool)
        except np.linalg.LinAlgError:
            singular = None
    sol = np.empty_like(flat_r)
    for attempt in range(2):
        if singular is None:
            sign, _ = np.linalg.slogdet(flat_s)  # the LU of solve: sign 0 <=> an exactly zero pivot
            singular = sign == 0
        try:
            sol[~singular] = np.linalg.solve(flat_s[~singular], flat_r[~singular])
            break
        except np.linalg.LinAlgError:
            # the guess missed one; after the slogdet split, LU and slogdet disagreeing is
            # left to least squares for the whole batch
            singular = None if attempt == 0 else np.ones(len(flat_s), bool)
    if singular.any():
        pinv = np.linalg.pinv(flat_s[singular], rcond=np.finfo(np.float64).eps * n)
        sol[singular] = pinv @ flat_r[singular]
    return sol.reshape(rhs.shape), singular


def fit_tps(source_points, target_points, *, regularization=0.0, weights=None, affine_regularization=0.0):
    """Fit the thin-plate spline taking ``source_points`` onto ``target_points``.

    Parameters
    ----------
    source_points, target_points : array_like, shape (..., K, 2)
        Control points ``x_a`` and their targets ``y_a``; leading axes are a
        batch of independent splines.
    regularization : float or array_like, shape (...)
        ``lambda >= 0``: 0 interpolates the targets exactly (needs ``K >= 3``
        points not on a line); large values tend to the (weighted)
        least-squares affine fit.
    weights : array_like, shape (..., K), optional
        Non-negative confidence ``w_a`` of each pair; 0 marks padding (the
        point is ignored). Default all 1.
    affine_regularization : float or array_like, shape (...)
        Ridge ``lambda_2 |D - I|^2`` pulling the affine part towards the
        identity (Chui and Rangarajan 2000); 0 by default.

    Returns
    -------
    ThinPlateSpline

    Raises
    ------
    ValueError
        For shapes that are not ``(..., K, 2)`` or differ, non-finite points,
        fewer than 3 points, negative weights or regularisation.

    Notes
    -----
    Minimises ``sum_a w_a |y_a - f(x_a)|^2 + lambda c^T Phi c`` with
    ``Phi_ab = U(|x_a - x_b|)``, ``U(r) = r^2 log r``; the bending energy is
    ``J(f) = 8 pi c^T Phi c``. With ``lambda = 0`` this is Bookstein's
    interpolating spline (1989, eq. 4); with unit weights it is
    ``scipy.interpolate.RBFInterpolator(kernel="thin_plate_spline",
    smoothing=lambda)``.

    References
    ----------
    .. [1] F. L. Bookstein, "Principal warps: thin-plate splines and the
       decomposition of deformations", IEEE PAMI 11(6), 1989.
       :doi:`10.1109/34.24792`

    Examples
    --------
    >>> src = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0], [1.0, 1.0]])
    >>> dst = src + [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.2, 0.1]]
    >>> tps = fit_tps(src, dst)
    >>> bool(np.allclose(tps(src), dst))
    True
    >>> bool(np.allclose(fit_tps(src, src)(np.array([[0.3, 0.7]])), [[0.3, 0.7]]))
    True
    """
    src = _as_points(source_points, "source_points")
    dst = _as_points(target_points, "target_points")
    if src.shape != dst.shape:
        raise ValueError(f"source_points {src.shape} and target_points {dst.shape} must have the same shape")
    if src.shape[-2] < 3:
        raise ValueError(f"a TPS needs at least 3 points (K >= 3), got K = {src.shape[-2]}")
    if weights is None:
        w = np.ones(src.shape[:-1])
    else:
        w = np.asarray(weights, dtype=np.float64)
        if w.shape != src.shape[:-1]:
            raise ValueError(f"weights must have shape {src.shape[:-1]}, got {w.shape}")
        if not np.all(np.isfinite(w)) or w.min() < 0:
            raise ValueError("weights must be finite and non-negative")
    lam = np.asarray(regularization, dtype=np.float64)
    lam2 = np.asarray(affine_regularization, dtype=np.float64)
    for name, value in (("regularization", lam), ("affine_regularization", lam2)):
        if not np.all(np.isfinite(value)) or np.any(value < 0):
            raise ValueError(f"{name} must be finite and >= 0, got {value}")
    coef, affine = _TPSSystem(src).solve(dst, w, lam, lam2)
    return ThinPlateSpline(src, coef, affine)


def _as_points(points, name):
    arr = np.asarray(points, dtype=np.float64)
    if arr.ndim < 2 or arr.shape[-1] != 2:
        raise ValueError(f"{name} must have shape (..., K, 2), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return arr


@dataclass(frozen=True)
class TPSRPMResult:
    """Result of :func:`tps_rpm`.

    Attributes
    ----------
    forward : ThinPlateSpline
        ``theta_12``: maps the first point set ``X`` onto ``Y``.
    backward : ThinPlateSpline
        ``theta_21``: maps ``Y`` onto ``X``, fitted with the same final
        correspondences (Ruiters et al. 2010, Section 4.2).
    match : numpy.ndarray, shape (..., K + 1, N + 1)
        Final soft-assignment matrix; the last row / column are outliers.
    temperatures : numpy.ndarray, shape (...)
        Number of annealing temperatures each problem went through.
    """

    forward: ThinPlateSpline
    backward: ThinPlateSpline
    match: np.ndarray
    temperatures: np.ndarray


def _sinkhorn(kernel, eps_rows, eps_cols, iterations, tol):
    """Alternating row/column normalisation with an outlier row and column.

    The full matrix is ``[[kernel, eps_rows], [eps_cols, 0]]`` of shape
    (..., K+1, N+1): inlier rows are normalised over all N+1 columns and
    inlier columns over all K+1 rows; the outlier entries take part but are
    not normalised themselves. Written with scaling vectors (Sinkhorn-Knopp,
    ``m_ai = u_a k_ai v_i``), which is the same iteration at the cost of two
    matrix-vector products. Returns ``(m, m_outlier_column, m_outlier_row)``.
    """
    v = np.ones(kernel.shape[:-2] + (kernel.shape[-1],))
    u = None
    for _ in range(iterations):
        u_new = 1.0 / np.maximum((kernel @ v[..., None])[..., 0] + eps_rows, 1e-300)
        v = 1.0 / np.maximum((u_new[..., None, :] @ kernel)[..., 0, :] + eps_cols, 1e-300)
        if u is not None and tol and np.max(np.abs(u_new - u) / u_new, initial=0.0) < tol:
            u = u_new
            break
        u = u_new
    m = u[..., :, None] * kernel * v[..., None, :]
    return m, u * eps_rows, eps_cols * v


def tps_rpm(X, Y, *, x_weights=None, y_weights=None, initial_temperature=None, final_temperature=None,
            anneal_rate=0.93, lambda_init=1.0, affine_lambda_init=0.01, iterations_per_temperature=5,
            sinkhorn_iterations=30, outlier_weight=None, outliers_to_own_position=True):
    """Non-rigid point matching by TPS-RPM (Chui and Rangarajan 2000).

    Parameters
    ----------
    X : array_like, shape (..., K, 2)
        The point set that is deformed ("model" points ``v_a``).
    Y : array_like, shape (..., N, 2)
        The target point set ("data" points ``x_i``).
    x_weights, y_weights : array_like of bool or 0/1, shape (..., K) / (..., N), optional
        Masks for padded batches: 0 marks a padding point. Each problem needs
        at least 3 valid points in ``X`` and 1 in ``Y``.
    initial_temperature : float, optional
        ``T_init``; default, per problem, the largest squared distance of all
        point pairs (Chui and Rangarajan 2000, Section 4).
    final_temperature : float, optional
        ``T_final``; default, per problem, ``T_init / 500`` (``T_finalfac =
        500`` of the authors' released code). The article's alternative, the
        mean squared nearest-neighbour distance within ``X``, left the
        assignment visibly soft in our tests (identical sets were matched
        only to 3.7 px), so it is not the default.
    anneal_rate : float
        ``T <- anneal_rate * T`` after each temperature; 0.93 as in the paper.
    lambda_init, affine_lambda_init : float
        The TPS regularisation annealed with the temperature,
        ``lambda = lambda_init * K * T`` and ``lambda_2 = affine_lambda_init
        * K * T`` (1 and 0.01 in the authors' implementation).
    iterations_per_temperature : int
        Alternations of correspondence and TPS updates per temperature (5).
    sinkhorn_iterations : int
        Upper bound of Sinkhorn row/column normalisations per update (30; it
        stops earlier when the rows sum to 1 within 1e-3).
    outlier_weight : float, optional
        The constant entries of the outlier row and column, against which
        ``exp(-|y_i - f(x_a)|^2 / 2T)`` competes: a point whose best match
        scores below it is an outlier. Default ``0.1 / K`` as in the authors'
        RPM code.
    outliers_to_own_position : bool
        Ruiters et al. 2010's modification: in the last iteration the mass a
        point gives to the outlier column pulls it towards its *own*
        position, so outliers keep the warp near the identity instead of
        dragging it to distant features. ``False`` gives the original
        algorithm (the last fit uses the normalised inlier matches only).

    Returns
    -------
    TPSRPMResult
        ``forward`` (X -> Y), ``backward`` (Y -> X, same correspondences),
        the final ``match`` matrix and the number of temperatures.

    Raises
    ------
    ValueError
        For malformed point sets, too few valid points, or parameters out of
        range (``anneal_rate`` must lie in (0, 1)).

    Notes
    -----
    Chui and Rangarajan minimise (their eq. 3; Ruiters et al. eq. 1)

    .. math:: E(M, f) = \\sum_{a,i} m_{ai} |x_i - f(v_a)|^2 + \\lambda J(f)
              + T \\sum_{a,i} m_{ai} \\log m_{ai} - \\zeta \\sum_{a,i} m_{ai}

    by alternating the soft assignment ``m_ai = exp(-|x_i - f(v_a)|^2 / 2T)``
    (made doubly stochastic, with the outlier row/column, by Sinkhorn) and
    the TPS fit to ``y_a = sum_i m_ai x_i / sum_i m_ai`` with weights
    ``sum_i m_ai`` (the exact minimiser of the first term), lowering ``T``
    geometrically from ``T_init`` to ``T_final``.

    References
    ----------
    .. [1] H. Chui and A. Rangarajan, "A new algorithm for non-rigid point
       matching", CVPR 2000. :doi:`10.1109/CVPR.2000.854733`
    .. [2] R. Ruiters, R. Schnabel and R. Klein, "Patch-based texture
       interpolation", EGSR 2010. :doi:`10.1111/j.1467-8659.2010.01739.x`

    Examples
    --------
    A shifted square with one outlier added to the target set:

    >>> X = np.array([[0.0, 0], [0, 4], [4, 0], [4, 4], [2, 2]])
    >>> Y = np.vstack([X + [0.5, 0.3], [[20.0, 20.0]]])
    >>> result = tps_rpm(X, Y)
    >>> np.round((result.forward(X) - X).mean(axis=0), 1).tolist()
    [0.5, 0.3]
    """
    # Many small solves: threaded BLAS only adds contention (10x slower
    # measured on the 2-core machine), so run single-threaded.
    with one_blas_thread():
        return _tps_rpm(X, Y, x_weights, y_weights, initial_temperature, final_temperature, anneal_rate,
                        lambda_init, affine_lambda_init, iterations_per_temperature, sinkhorn_iterations,
                        outlier_weight, outliers_to_own_position)


def _tps_rpm(X, Y, x_weights, y_weights, initial_temperature, final_temperature, anneal_rate, lambda_init,
             affine_lambda_init, iterations_per_temperature, sinkhorn_iterations, outlier_weight,
             outliers_to_own_position):
    X = _as_points(X, "X")
    Y = _as_points(Y, "Y")
    if X.shape[:-2] != Y.shape[:-2]:
        raise ValueError(f"X {X.shape} and Y {Y.shape} must have the same batch shape")
    anneal_rate = check_in_range(anneal_rate, "anneal_rate", 0.0, 1.0, low_open=True, high_open=True)
    lambda_init = check_positive_float(lambda_init, "lambda_init", allow_zero=True)
    affine_lambda_init = check_positive_float(affine_lambda_init, "affine_lambda_init", allow_zero=True)
    iterations_per_temperature = check_positive_int(iterations_per_temperature, "iterations_per_temperature")
    sinkhorn_iterations = check_positive_int(sinkhorn_iterations, "sinkhorn_iterations")
    xv = _mask(x_weights, X.shape[:-1], "x_weights")
    yv = _mask(y_weights, Y.shape[:-1], "y_weights")
    kx = xv.sum(axis=-1)
    if np.any(kx < 3) or np.any(yv.sum(axis=-1) < 1):
        raise ValueError("every problem needs at least 3 valid points in X and 1 in Y")
    k, n = X.shape[-2], Y.shape[-2]

    # Centre both sets on X's centroid: better conditioned, same warp.
    centre = (X * xv[..., None]).sum(-2, keepdims=True) / kx[..., None, None]
    Xc, Yc = X - centre, Y - centre
    pair = xv[..., :, None] & yv[..., None, :]
    d2 = _sq_dist(Xc, Yc)
    if initial_temperature is None:
        t_init = np.where(pair, d2, 0.0).max(axis=(-2, -1))
        t_init = np.maximum(t_init, 1e-12)
    else:
        t_init = np.full(X.shape[:-2], check_positive_float(initial_temperature, "initial_temperature"))
    if final_temperature is None:
        t_final = t_init / 500.0  # T_finalfac = 500 of the authors' code
    else:
        t_final = np.full(X.shape[:-2], check_positive_float(final_temperature, "final_temperature"))
    eps = 0.1 / kx if outlier_weight is None else np.full(X.shape[:-2], check_positive_float(
        outlier_weight, "outlier_weight"))
    # number of temperatures per problem: T_init * r^(n-1) >= T_final
    n_temps = 1 + np.floor(np.log(np.maximum(t_final, 1e-300) / t_init) / np.log(anneal_rate) + 1e-9)
    n_temps = np.maximum(n_temps, 1).astype(np.int64)

    sys_x = _TPSSystem(Xc)
    phi_x = sys_x.phi
    coef = np.zeros(X.shape)
    affine = np.zeros(X.shape[:-2] + (3, 2))
    affine[..., 1:, :] = np.eye(2)
    m_in = np.zeros(X.shape[:-2] + (k, n))
    m_oc = np.zeros(X.shape[:-1])
    m_or = np.zeros(Y.shape[:-1])
    kfac = kx.astype(np.float64)
    for step in range(int(n_temps.max())):
        active = step < n_temps
        last_temp = step == n_temps - 1
        temp = t_init * anneal_rate ** step
        for it in range(iterations_per_temperature):
            final = last_temp & (it == iterations_per_temperature - 1)
            # correspondence update: V = f(X), m_ai = exp(-|x_i - v_a|^2 / 2T)
            v = _affine_basis(Xc) @ affine + phi_x @ coef
            dist = _sq_dist(v, Yc)
            kern = np.exp(-dist / (2.0 * temp[..., None, None])) * pair
            inl, out_col, out_row = _sinkhorn(kern, eps[..., None] * xv, eps[..., None] * yv,
                                              sinkhorn_iterations, 1e-3)
            m_in = np.where(active[..., None, None], inl, m_in)
            m_oc = np.where(active[..., None], out_col, m_oc)
            m_or = np.where(active[..., None], out_row, m_or)
            # transformation update: weighted targets y_a (exact minimiser of eq. 1's first term)
            mass = m_in.sum(-1)
            target = m_in @ Yc / np.maximum(mass, 1e-300)[..., None]
            w = mass * xv
            if outliers_to_own_position:
                # Ruiters et al.: outlier mass goes to the point's own position
                own = m_in @ Yc + m_oc[..., None] * Xc
                own_w = (mass + m_oc) * xv
                target = np.where(final[..., None, None], own / np.maximum(own_w, 1e-300)[..., None], target)
                w = np.where(final[..., None], own_w, w)
            w = np.where(xv, np.maximum(w, 1e-8), 0.0)
            lam = lambda_init * kfac * temp
            lam2 = affine_lambda_init * kfac * temp
            c_new, a_new = sys_x.solve(target, w, lam, lam2)
            coef = np.where(active[..., None, None], c_new, coef)
            affine = np.where(active[..., None, None], a_new, affine)

    # backward TPS theta_21 from the same final correspondences
    mass_y = m_in.sum(-2)
    if outliers_to_own_position:
        back_t = np.swapaxes(m_in, -1, -2) @ Xc + m_or[..., None] * Yc
        back_w = mass_y + m_or
    else:
        back_t = np.swapaxes(m_in, -1, -2) @ Xc
        back_w = mass_y
    back_t = back_t / np.maximum(back_w, 1e-300)[..., None]
    back_w = np.where(yv, np.maximum(back_w, 1e-8), 0.0)
    t_end = t_init * anneal_rate ** (n_temps - 1)
    kyf = yv.sum(-1).astype(np.float64)
    if np.any(kyf < 3):
        # fewer than 3 data points: the backward warp is the inverse affine part only
        back_w = np.where((kyf < 3)[..., None], 0.0, back_w)
    bc, ba = _solve_tps_safe(Yc, back_t, back_w, lambda_init * kyf * t_end,
                             affine_lambda_init * kyf * t_end, affine, kyf < 3)
    forward = _uncentre(ThinPlateSpline(Xc, coef, affine), centre)
    backward = _uncentre(ThinPlateSpline(Yc, bc, ba), centre)
    m = np.zeros(X.shape[:-2] + (k + 1, n + 1))
    m[..., :-1, :-1] = m_in
    m[..., :-1, -1] = m_oc
    m[..., -1, :-1] = m_or
    return TPSRPMResult(forward, backward, m, n_temps)


def _solve_tps_safe(points, targets, weights, lam, lam2, forward_affine, degenerate):
    """Backward fit; problems with < 3 valid points get the inverse forward affine map."""
    w = np.where(degenerate[..., None], 1.0, weights)  # keep the system regular
    pts = points
    coef, affine = _TPSSystem(pts).solve(targets, w, lam, lam2)
    if np.any(degenerate):
        lin = forward_affine[..., 1:, :]
        off = forward_affine[..., :1, :]
        inv = np.linalg.inv(lin + 1e-12 * np.eye(2))
        inv_aff = np.concatenate([-off @ inv, inv], axis=-2)
        affine = np.where(degenerate[..., None, None], inv_aff, affine)
        coef = np.where(degenerate[..., None, None], 0.0, coef)
    return coef, affine


def _uncentre(tps, centre):
    """Express a spline fitted in coordinates centred at ``centre`` in the original ones."""
    pts = tps.control_points + centre
    aff = tps.affine.copy()
    # f(x) = f_c(x - c) + c, f_c(u) = a0 + u D + ... -> a0' = a0 - c D + c
    aff[..., :1, :] = aff[..., :1, :] - centre @ aff[..., 1:, :] + centre
    return ThinPlateSpline(pts, tps.coefficients, aff)


def _mask(weights, shape, name):
    if weights is None:
        return np.ones(shape, dtype=bool)
    w = np.asarray(weights)
    if w.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {w.shape}")
    return w > 0
