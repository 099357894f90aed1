"""Tests of thin-plate splines and TPS-RPM point matching (texsynth.core.tps)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import RBFInterpolator

from texsynth.core.tps import ThinPlateSpline, _solve_or_lstsq, fit_tps, tps_kernel, tps_rpm


def smooth_warp(p):
    """A known smooth non-rigid warp of the plane (translation + sinusoidal bend)."""
    return p + np.stack([2.0 * np.sin(p[:, 1] / 8.0), 1.5 * np.cos(p[:, 0] / 9.0)], axis=1) + [1.0, 0.5]


def jittered_grid(rng, step=3.0, extent=30.0, jitter=0.3):
    g = np.stack(np.meshgrid(np.arange(0, extent, step), np.arange(0, extent, step)), -1).reshape(-1, 2)
    return g + rng.normal(0, jitter, g.shape)


# --------------------------------------------------------------------------- #
# thin-plate splines
# --------------------------------------------------------------------------- #
@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 25))
def test_tps_interpolates_control_points_exactly(seed, k):
    rng = np.random.default_rng(seed)
    src = rng.uniform(0, 30, (k, 2))
    dst = src + rng.normal(0, 3, (k, 2))
    np.testing.assert_allclose(fit_tps(src, dst)(src), dst, atol=1e-7)


def test_tps_matches_scipy_rbf_interpolator():
    # Independent reference: scipy's thin_plate_spline RBF with a degree-1 polynomial
    # solves the same system (K + lambda I) c + P d = y.
    rng = np.random.default_rng(3)
    src = rng.uniform(0, 30, (20, 2))
    dst = src + rng.normal(0, 2, (20, 2))
    queries = rng.uniform(-5, 35, (100, 2))
    for lam in (0.0, 1.0, 100.0):
        ref = RBFInterpolator(src, dst, kernel="thin_plate_spline", smoothing=lam)(queries)
        np.testing.assert_allclose(fit_tps(src, dst, regularization=lam)(queries), ref, atol=1e-8)


def test_tps_tends_to_affine_least_squares_as_lambda_grows():
    rng = np.random.default_rng(4)
    src = rng.uniform(0, 30, (15, 2))
    dst = src @ np.array([[1.1, 0.2], [-0.1, 0.9]]) + 3 + rng.normal(0, 2, (15, 2))
    basis = np.hstack([np.ones((15, 1)), src])
    affine = np.linalg.lstsq(basis, dst, rcond=None)[0]
    queries = rng.uniform(0, 30, (50, 2))
    expected = np.hstack([np.ones((50, 1)), queries]) @ affine
    errors = [np.abs(fit_tps(src, dst, regularization=lam)(queries) - expected).max() for lam in (1e2, 1e4, 1e6, 1e8)]
    assert all(b < a for a, b in zip(errors, errors[1:]))  # monotone approach
    assert errors[-1] < 1e-4  # lambda=1e8: the radial part is ~1e-8 of the data misfit
    # and the far-from-affine lambda = 0 spline is not close (the test would notice no effect)
    assert np.abs(fit_tps(src, dst)(queries) - expected).max() > 0.5


def test_identity_for_identical_point_sets():
    rng = np.random.default_rng(5)
    pts = rng.uniform(0, 20, (12, 2))
    for lam in (0.0, 10.0):
        tps = fit_tps(pts, pts, regularization=lam)
        queries = rng.uniform(-10, 30, (40, 2))
        np.testing.assert_allclose(tps(queries), queries, atol=1e-8)
        assert abs(tps.bending_energy) < 1e-8
    # TPS-RPM on identical sets: the assignment at T_final is still slightly soft
    # (measured max deviation 0.20 px on a 20 px set, points 4 px apart), so 0.3 px.
    res = tps_rpm(pts, pts)
    np.testing.assert_allclose(res.forward(pts), pts, atol=0.3)
    np.testing.assert_allclose(res.backward(pts), pts, atol=0.3)


def test_bending_energy_matches_numerical_integral():
    # J(f) = integral of f_xx^2 + 2 f_xy^2 + f_yy^2 over the plane, by finite differences
    rng = np.random.default_rng(6)
    src = rng.uniform(-1, 1, (6, 2))
    tps = fit_tps(src, src + rng.normal(0, 0.2, (6, 2)))
    h, extent = 0.05, 25.0
    ax = np.arange(-extent, extent + h / 2, h)
    gx, gy = np.meshgrid(ax, ax, indexing="ij")
    f = tps(np.stack([gx.ravel(), gy.ravel()], 1)).reshape(len(ax), len(ax), 2)
    fxx = (f[2:, 1:-1] - 2 * f[1:-1, 1:-1] + f[:-2, 1:-1]) / h**2
    fyy = (f[1:-1, 2:] - 2 * f[1:-1, 1:-1] + f[1:-1, :-2]) / h**2
    fxy = (f[2:, 2:] - f[2:, :-2] - f[:-2, 2:] + f[:-2, :-2]) / (4 * h**2)
    numeric = ((fxx**2 + 2 * fxy**2 + fyy**2).sum() * h**2)
    # measured 49.3 vs 52.3 (-6 %): finite differences underestimate the log singularity
    # of U_xx at the knots; a wrong constant (4 pi, 16 pi) would be off by 50 % or more.
    assert numeric == pytest.approx(float(tps.bending_energy), rel=0.08)


def test_batched_fit_equals_single_fits_and_zero_weight_is_padding():
    rng = np.random.default_rng(7)
    src = rng.uniform(0, 30, (4, 10, 2))
    dst = src + rng.normal(0, 2, (4, 10, 2))
    w = np.ones((4, 10))
    w[1, 7:] = 0  # padding: these three points must be ignored
    batch = fit_tps(src, dst, regularization=2.0, weights=w)
    q = rng.uniform(0, 30, (4, 20, 2))
    out = batch(q)
    for b in range(4):
        keep = w[b] > 0
        single = fit_tps(src[b, keep], dst[b, keep], regularization=2.0)
        np.testing.assert_allclose(out[b], single(q[b]), atol=1e-8)


def test_kernel_and_affine_part():
    assert tps_kernel(np.array([0.0]))[0] == 0.0
    tps = ThinPlateSpline(np.zeros((3, 2)), np.zeros((3, 2)), np.array([[1.0, 2.0], [1.0, 0.0], [0.0, 1.0]]))
    np.testing.assert_allclose(tps(np.array([[3.0, 4.0]])), [[4.0, 6.0]])


# --------------------------------------------------------------------------- #
# TPS-RPM
# --------------------------------------------------------------------------- #
def test_tps_rpm_recovers_known_smooth_warp_with_outliers():
    rng = np.random.default_rng(0)
    X = jittered_grid(rng)  # 100 points
    truth = smooth_warp(X)
    Y = np.vstack([truth, rng.uniform(0, 30, (10, 2))])  # 10 % outliers in the target set
    Y = Y[rng.permutation(len(Y))]  # correspondence unknown
    res = tps_rpm(X, Y)
    err = np.linalg.norm(res.forward(X) - truth, axis=1).mean()
    identity_err = np.linalg.norm(X - truth, axis=1).mean()
    # measured: 0.59 px vs 2.37 px for the identity (the regularisation lambda = K*T_final
    # keeps part of the bend); a wrong correspondence or sign gives > identity.
    assert err < 0.35 * identity_err
    back = np.linalg.norm(res.backward(truth) - X, axis=1).mean()
    assert back < 0.5 * identity_err
    # the outlier points of Y receive the outlier row's mass
    assert res.match.shape == (len(X) + 1, len(Y) + 1)


def test_tps_rpm_own_position_modification_limits_outlier_pull():
    # X has 4 extra points with no partner in Y, far from everything; the original
    # algorithm's last fit drags them towards the nearest data, Ruiters' variant keeps
    # them near their own position (less deformation).
    rng = np.random.default_rng(1)
    X = jittered_grid(rng, step=4.0, extent=24.0)
    Y = X + [1.0, 0.0]
    extra = np.array([[-12.0, -12.0], [-12.0, 36.0], [36.0, -12.0], [36.0, 36.0]])
    X2 = np.vstack([X, extra])
    # final_temperature=1: with the default T_init / 500 (= 9 here, the far extra points
    # inflate T_init) the last assignment between 4 px neighbours is still soft.
    own = tps_rpm(X2, Y, outliers_to_own_position=True, final_temperature=1.0)
    orig = tps_rpm(X2, Y, outliers_to_own_position=False, final_temperature=1.0)
    move_own = np.linalg.norm(own.forward(extra) - extra, axis=1).mean()
    move_orig = np.linalg.norm(orig.forward(extra) - extra, axis=1).mean()
    assert move_own < move_orig
    # and the inliers are still matched (translation by 1 px recovered to 0.2 px)
    assert np.abs(own.forward(X) - Y).mean() < 0.2


def test_tps_rpm_batched_with_padding_equals_single():
    rng = np.random.default_rng(2)
    X = rng.uniform(0, 16, (2, 12, 2))
    Y = X + [0.8, -0.5] + rng.normal(0, 0.2, X.shape)
    xw = np.ones((2, 12))
    xw[1, 9:] = 0
    yw = np.ones((2, 12))
    yw[1, 10:] = 0
    batch = tps_rpm(X, Y, x_weights=xw, y_weights=yw)
    single = tps_rpm(X[1, :9], Y[1, :10])
    q = rng.uniform(0, 16, (30, 2))
    np.testing.assert_allclose(batch.forward(np.stack([q, q]))[1], single.forward(q), atol=1e-6)
    np.testing.assert_allclose(batch.backward(np.stack([q, q]))[1], single.backward(q), atol=1e-6)


def test_tps_rpm_is_deterministic():
    rng = np.random.default_rng(3)
    X = rng.uniform(0, 10, (8, 2))
    a = tps_rpm(X, X + 0.5)
    b = tps_rpm(X, X + 0.5)
    assert np.array_equal(a.forward.coefficients, b.forward.coefficients)


# --------------------------------------------------------------------------- #
# bad input
# --------------------------------------------------------------------------- #
def test_bad_input():
    pts = np.zeros((5, 2))
    with pytest.raises(ValueError, match="source_points"):
        fit_tps(np.zeros((5, 3)), pts)
    with pytest.raises(ValueError, match="same shape"):
        fit_tps(pts, np.zeros((4, 2)))
    with pytest.raises(ValueError, match="at least 3"):
        fit_tps(np.zeros((2, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="regularization"):
        fit_tps(np.random.rand(5, 2), np.random.rand(5, 2), regularization=-1)
    with pytest.raises(ValueError, match="weights"):
        fit_tps(np.random.rand(5, 2), np.random.rand(5, 2), weights=-np.ones(5))
    with pytest.raises(ValueError, match="NaN"):
        fit_tps(np.full((5, 2), np.nan), pts)
    with pytest.raises(ValueError, match="anneal_rate"):
        tps_rpm(np.random.rand(5, 2), np.random.rand(5, 2), anneal_rate=1.0)
    with pytest.raises(ValueError, match="at least 3 valid"):
        tps_rpm(np.random.rand(2, 2), np.random.rand(5, 2))
    with pytest.raises(ValueError, match="batch shape"):
        tps_rpm(np.random.rand(2, 5, 2), np.random.rand(3, 5, 2))


def test_singular_systems_in_a_batch_get_least_squares_the_others_lu():
    # a batch where every third system is singular (a zero row and column, as a padded or
    # degenerate problem gives): those must get numpy's minimum-norm lstsq solution, the
    # others the LU solution, without one failure switching the whole batch to lstsq
    rng = np.random.default_rng(3)
    systems = rng.normal(size=(12, 7, 7)) + 7 * np.eye(7)
    systems[::3, 2, :] = 0.0
    systems[::3, :, 2] = 0.0
    rhs = rng.normal(size=(12, 7, 2))
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.solve(systems, rhs)
    out, singular = _solve_or_lstsq(systems, rhs)
    assert singular.tolist() == [i % 3 == 0 for i in range(12)]
    # a second solve with that split (as TPS-RPM refits the same control points) gives the same
    again, _ = _solve_or_lstsq(systems, rhs, singular)
    np.testing.assert_allclose(again, out, atol=1e-12)
    # a wrong split is corrected
    wrong, _ = _solve_or_lstsq(systems, rhs, ~singular)
    np.testing.assert_allclose(wrong, out, atol=1e-10)
    for i in range(12):
        ref = (np.linalg.lstsq(systems[i], rhs[i], rcond=None)[0] if i % 3 == 0
               else np.linalg.solve(systems[i], rhs[i]))
        np.testing.assert_allclose(out[i], ref, atol=1e-10)


def test_collinear_control_points_in_a_batch():
    # feature pixels along a straight mortar joint are collinear: their TPS system is singular.
    # Shifting the line along itself must still be fitted exactly, and the other problem of
    # the batch must be the same as fitted alone.
    line = np.stack([np.zeros(6), np.arange(6.0)], 1)  # on the row y = 0
    rng = np.random.default_rng(4)
    free = rng.uniform(0, 10, (6, 2))
    src = np.stack([line, free])
    dst = src + [[[0.0, 1.5]], [[0.5, -0.5]]]
    batch = fit_tps(src, dst)
    np.testing.assert_allclose(batch(src)[0], dst[0], atol=1e-8)
    np.testing.assert_allclose(batch(src)[1], dst[1], atol=1e-8)
    q = rng.uniform(0, 10, (5, 2))
    np.testing.assert_allclose(batch(np.stack([q, q]))[1], fit_tps(free, dst[1])(q), atol=1e-10)
