"""Dynamic textures (Doretto, Chiuso, Wu & Soatto 2003): identification, stability, quality, validation.

Clips are made here: a linear-Gaussian system with known poles (identification), a shaded 2-D wave
equation stirred by random drops (water, the quality checks), a rotating sinusoid.
"""

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.linalg import solve_discrete_lyapunov

from texsynth import metrics
from texsynth.core._validate import memory_limit
from texsynth.core.coordinates import apply_coordinates
from texsynth import data
from texsynth.metrics import temporal_correlation
from texsynth.video import DynamicTexture, DynamicTextureInfo, dynamic_texture, learn_dynamic_texture
from texsynth.video._doretto import run_states, stabilize

POLES = (0.95 * np.exp(0.3j), 0.85 * np.exp(1.0j))


def lds_clip(seed, T=500, side=16, noise=0.002):
    """A grey clip from x(t+1) = A x(t) + v(t), y = C x + 0.5 + w: poles POLES (and conjugates) in a random
    state basis, C a random orthonormal 256 x 4 matrix. Returns (clip, true eigenvalues, true C)."""
    gen = np.random.default_rng(seed)
    A = np.zeros((4, 4))
    for k, p in enumerate(POLES):
        A[2 * k:2 * k + 2, 2 * k:2 * k + 2] = [[p.real, -p.imag], [p.imag, p.real]]
    Z, _ = np.linalg.qr(gen.standard_normal((4, 4)))
    A = Z @ A @ Z.T
    C, _ = np.linalg.qr(gen.standard_normal((side * side, 4)))
    X = run_states(A, np.eye(4), np.zeros(4), T + 50, gen)[:, 50:]  # 50 frames of burn-in
    Y = C @ X
    Y = 0.5 + 0.35 * Y / np.abs(Y).max() + noise * gen.standard_normal(Y.shape)
    poles = np.array(list(POLES) + [np.conj(p) for p in POLES])
    return np.clip(Y.T.reshape(T, side, side), 0, 1), poles, C


def water_clip(seed, T=64, side=40):
    """(T, side, side, 3): texsynth.data's choppy water, small."""
    return data.clip("waves", T, side, rng=seed)


def wave(T=24, H=12, W=16):
    """A sinusoid moving right by 0.3 rad a frame: rank 2, a rotation of two components."""
    t, c = np.arange(T)[:, None, None], np.arange(W)[None, None, :]
    return 0.5 + 0.4 * np.sin(0.5 * c - 0.3 * t) * np.ones((1, H, 1))


@pytest.fixture(scope="module")
def water():
    return water_clip(0)


# ---------------------------------------------------------------------------- the closed form


@pytest.mark.parametrize("estimator", ["yule-walker", "least-squares"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_identification_recovers_the_poles_and_the_subspace(seed, estimator):
    clip, poles, C_true = lds_clip(seed)
    model = learn_dynamic_texture(clip, state_dim=4, estimator=estimator)
    # eigenvalues are invariant to the state basis: each true pole has a learnt one near it (8 seeds
    # measured: at most 0.034 from 500 frames, either estimator; bound 0.08, a margin of 2.4)
    learnt = np.linalg.eigvals(model.A)
    assert max(np.min(np.abs(learnt - p)) for p in poles) < 0.08
    # C spans the true output subspace: all principal angles near 0 (measured cosines > 0.9999)
    assert np.linalg.svd(model.C.T @ C_true, compute_uv=False).min() > 0.99
    assert learn_dynamic_texture(clip).state_dim == 4  # "auto" finds the 4 dimensions


def test_the_steps_of_the_closed_form(water):
    model = learn_dynamic_texture(water, state_dim=10, estimator="least-squares")
    T = len(water)
    Y = water.reshape(T, -1).T - water.reshape(T, -1).mean(0)[:, None]
    C, X = np.asarray(model.C), model.states
    np.testing.assert_allclose(C.T @ C, np.eye(10), atol=1e-10)  # C = U_n, orthonormal
    np.testing.assert_allclose(X, C.T @ Y, atol=1e-9)  # X = S_n V_n^T = C^T Y
    s = np.linalg.svd(Y, compute_uv=False)  # the Gram route gives LAPACK's singular values
    np.testing.assert_allclose(model.singular_values[:20], s[:20], rtol=1e-8)
    np.testing.assert_allclose(np.sqrt(np.sum(X**2, axis=1)), s[:10], rtol=1e-8)
    A_ls = X[:, 1:] @ np.linalg.pinv(X[:, :-1])  # A = X_2^T (X_1^{T-1})^+
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(A_ls)), np.sort_complex(model.eigenvalues),
                               atol=1e-9)
    if not model.stabilized:
        np.testing.assert_allclose(model.A, A_ls, atol=1e-10)
    residual = X[:, 1:] - A_ls @ X[:, :-1]
    np.testing.assert_allclose(model.Q, residual @ residual.T / (T - 1), atol=1e-10)  # B B^T = Q
    R = np.mean((Y - C @ X) ** 2, axis=1)  # the diagonal of R, from the residual of the frames
    np.testing.assert_allclose(model.R.reshape(-1), R, atol=1e-12)
    np.testing.assert_allclose(model.mean, water.mean(0), atol=1e-12)
    np.testing.assert_allclose(model.x0, X[:, 0])


def test_yule_walker_keeps_the_clips_covariances(water):
    """Yule-Walker: the stationary state covariance is the clip's S_0 and the lag-1 one its S_1, exactly."""
    model = learn_dynamic_texture(water)
    X, T = model.states, water.shape[0]
    S0, S1 = X @ X.T / T, X[:, 1:] @ X[:, :-1].T / T
    assert not model.stabilized and model.spectral_radius < 1
    P = solve_discrete_lyapunov(model.A, model.Q)
    np.testing.assert_allclose(P, S0, atol=1e-8 * np.trace(S0))
    np.testing.assert_allclose(model.A @ P, S1, atol=1e-8 * np.trace(S0))
    assert np.linalg.eigvalsh(model.Q).min() > -1e-10 * np.trace(S0)


def test_the_model_is_frozen(water):
    model = learn_dynamic_texture(water, state_dim=4)
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.A = np.eye(4)
    with pytest.raises(ValueError):
        model.A[0, 0] = 2.0  # read-only arrays
    assert model.modes.shape == (4, 40, 40, 3) and model.frame_shape == (40, 40, 3)
    assert model.state_dim == 4 and model.noise_dim == 4 and model.estimator == "yule-walker"


# ---------------------------------------------------------------------------- stability


def test_stabilize_moves_only_the_eigenvalues_on_or_outside_the_unit_circle():
    gen = np.random.default_rng(0)
    Z, _ = np.linalg.qr(gen.standard_normal((6, 6)))
    lam = [1.3 * np.exp(0.4j), 1.0, 0.5 * np.exp(2.0j), 0.995]  # a pair outside, one on, a pair and one inside
    D = np.zeros((6, 6))
    D[0:2, 0:2] = [[lam[0].real, -lam[0].imag], [lam[0].imag, lam[0].real]]
    D[2, 2] = lam[1]
    D[3:5, 3:5] = [[lam[2].real, -lam[2].imag], [lam[2].imag, lam[2].real]]
    D[5, 5] = lam[3]
    A, moved = stabilize(Z @ D @ Z.T)
    assert moved
    ev = np.linalg.eigvals(A)
    expected = [0.99 * np.exp(0.4j), 0.99 * np.exp(-0.4j), 0.99, lam[2], np.conj(lam[2]), 0.995]
    for e in expected:  # the pair keeps its angle, the others stay
        assert np.min(np.abs(ev - e)) < 1e-9
    inside = Z[:, :2] @ np.diag([0.3, -0.7]) @ Z[:, :2].T
    assert stabilize(inside)[1] is False and stabilize(inside)[0] is inside


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(1, 12), scale=st.floats(0.2, 3.0))
def test_stabilize_always_gives_a_stable_matrix(seed, n, scale):
    A = scale * np.random.default_rng(seed).standard_normal((n, n)) / np.sqrt(n)
    B, moved = stabilize(A)
    assert np.abs(np.linalg.eigvals(B)).max() < 1
    assert moved == (np.abs(np.linalg.eigvals(A)).max() >= 1 - 1e-9)


@pytest.mark.parametrize("estimator", ["yule-walker", "least-squares"])
def test_a_growing_clip_gives_a_stable_model(estimator):
    """A wave whose amplitude grows 2 % a frame: the least-squares A is outside the unit circle."""
    t = np.arange(40)[:, None, None]
    clip = 0.5 + 0.4 * 1.02 ** (t - 39) * np.sin(0.5 * np.arange(16)[None, None, :] - 0.3 * t) * np.ones((1, 8, 1))
    model = learn_dynamic_texture(clip, state_dim=2, estimator=estimator)
    assert model.spectral_radius < 1
    if estimator == "least-squares":
        assert model.stabilized and np.abs(model.eigenvalues).max() > 1.01
        np.testing.assert_allclose(np.abs(np.linalg.eigvals(model.A)), 0.99, atol=1e-9)
    video = model.synthesize(3000, rng=0)
    assert np.all(np.isfinite(video)) and video[-500:].std() < 0.4  # bounded after thousands of frames


def test_any_clip_gives_a_stable_model():
    for seed in range(6):
        gen = np.random.default_rng(seed)
        clip = gen.random((12, 6, 7)) ** (1 + seed)  # noise: anything may come out of least squares
        for estimator in ("yule-walker", "least-squares"):
            for n in (1, 3, 11):
                assert learn_dynamic_texture(clip, state_dim=n, estimator=estimator).spectral_radius < 1


# ---------------------------------------------------------------------------- synthesis


def test_synthesis_follows_the_model():
    model = learn_dynamic_texture(wave(), state_dim=2)
    video, info = model.synthesize(30, rng=0, return_info=True)
    assert isinstance(info, DynamicTextureInfo) and info.states.shape == (2, 30)
    X = info.states
    np.testing.assert_allclose(X[:, 0], model.x0)  # x(1) = x0, the clip's first state
    drive = X[:, 1:] - model.A @ X[:, :-1]  # = B v(t), in the span of B
    coef = np.linalg.lstsq(model.B, drive, rcond=None)[0]
    np.testing.assert_allclose(model.B @ coef, drive, atol=1e-10)
    expected = np.clip((np.asarray(model.C) @ X).T.reshape(30, 12, 16) + model.mean, 0, 1)  # y = C x + ybar
    np.testing.assert_allclose(video, expected, atol=1e-12)
    np.testing.assert_allclose(video[0], np.clip(wave()[0], 0, 1), atol=0.02)  # frame 1: the clip's, projected


def test_reproducible_with_the_same_rng(water):
    a = dynamic_texture(water, 20, rng=3)
    b = dynamic_texture(water, 20, rng=np.random.default_rng(3))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, dynamic_texture(water, 20, rng=4))
    model = learn_dynamic_texture(water)
    big = [model.synthesize(6, size=(48, 56), output_noise=True, rng=5) for _ in range(2)]
    assert np.array_equal(big[0], big[1])


def test_output_noise_adds_the_measurement_variance(water):
    model = learn_dynamic_texture(water, state_dim=6)
    plain = model.synthesize(200, rng=0)
    noisy = model.synthesize(200, output_noise=True, rng=0)
    added = (noisy - plain)[:, 4:-4, 4:-4]  # the same states (v is drawn first), plus w(t)
    # the per-value variance of w is R: pooled over 200 frames and 3 000 values, measured 1.002 of R's mean
    # (w is clipped with the frames: values near 0 and 1 would lose a little); bound 10 %
    assert abs(added.var() / model.R[4:-4, 4:-4].mean() - 1) < 0.1
    assert not np.array_equal(plain, noisy)


def test_dtypes_and_layouts():
    clip = wave()
    assert dynamic_texture(clip.astype(np.float32), 5, rng=0).dtype == np.float32
    assert dynamic_texture(clip, 5, rng=0).dtype == np.float64
    assert dynamic_texture((clip * 255).astype(np.uint8), 5, rng=0).shape == (5, 12, 16)
    assert dynamic_texture(clip[..., None], 5, rng=0).shape == (5, 12, 16, 1)
    colour = np.stack([clip, 1 - clip, clip * 0.5], -1)
    model = learn_dynamic_texture(colour)
    assert model.C.shape == (12 * 16 * 3, model.state_dim) and model.synthesize(4, rng=0).shape == (4, 12, 16, 3)


def test_a_static_clip_stays_static():
    frame = np.random.default_rng(0).random((6, 5))
    video = dynamic_texture(np.repeat(frame[None], 8, 0), 10, rng=0)
    np.testing.assert_allclose(video, np.repeat(frame[None], 10, 0), atol=1e-12)


def test_progress_reports_every_block(water):
    seen = []
    dynamic_texture(water, 5, rng=0, progress=lambda step, total, info: seen.append((step, total)))
    assert seen and seen[-1][0] == seen[-1][1]


# ---------------------------------------------------------------------------- quality


def _spectrum(video, clip, frames):
    return float(np.mean([metrics.spectrum_distance(video[t], clip[s]) for t in frames for s in (8, 40)]))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_frames_match_the_clips_statistics_and_motion(seed):
    """Per-frame statistics (spectrum distance to the clip's frames) and the lag-1 temporal correlation.

    Baselines computed here: histogram-matched white noise frames (right values, no structure) and the
    clip in shuffled order (every frame right, no motion). Measured on 4 seeds: the synthesis' spectrum
    distance lies 0.11-0.17 of the way from the clip's own frame-to-frame distance to the noise's
    (bound 0.3, a margin of 1.8); its lag-1 correlation within 0.01 of the clip's (0.90-0.91; bound
    0.05), the shuffled clip's 0.8-0.9 away (must be > 0.5); its temporal standard deviation 0.88-1.15 of
    the clip's (bounds 0.6-1.5).
    """
    clip = water_clip(seed)
    video = dynamic_texture(clip, 160, rng=seed)
    late = (100, 120, 140, 159)  # long after x0: the stationary regime
    own = _spectrum(clip, clip, (0, 20, 50, 63))
    noise = np.stack([metrics.noise_baseline(clip[t], clip.shape[1:3], rng=seed + t) for t in range(64)])
    noisy = _spectrum(noise, clip, (0, 20, 50, 63))
    assert (_spectrum(video, clip, late) - own) / (noisy - own) < 0.3

    target = temporal_correlation(clip)
    shuffled = clip[np.random.default_rng(seed).permutation(len(clip))]
    assert abs(temporal_correlation(video[32:]) - target) < 0.05
    assert abs(temporal_correlation(shuffled) - target) > 0.5  # the bound separates a clip without motion
    assert 0.6 < video[32:].std(0).mean() / clip.std(0).mean() < 1.5


def test_temporal_correlation():
    t = np.arange(50)[:, None, None]
    smooth = 0.5 + 0.4 * np.sin(0.1 * t + np.linspace(0, 3, 12).reshape(1, 3, 4))
    assert temporal_correlation(smooth) > 0.95
    assert temporal_correlation(np.repeat(smooth[:1], 5, 0)) == 0.0  # static
    alternating = 0.5 + 0.2 * (-1.0) ** t * np.ones((1, 3, 4))
    assert temporal_correlation(alternating) == pytest.approx(-1.0)
    with pytest.raises(ValueError, match="lag"):
        temporal_correlation(smooth[:1])


# ---------------------------------------------------------------------------- larger frames


def test_larger_frames_through_one_map_are_coherent(water):
    model = learn_dynamic_texture(water)
    small = model.synthesize(96, rng=1)
    video, info = model.synthesize(96, size=(72, 88), rng=1, return_info=True)
    assert video.shape == (96, 72, 88, 3) and info.coordinates.shape[:2] == (72, 88)
    # every frame goes through the one map: the mean frame with the convex weights, the motion C x(t) with
    # w / sqrt(sum w^2); rendered frame by frame here, as apply_coordinates does for any image
    w = info.weights
    balanced = w / np.sqrt(np.sum(w**2, -1, keepdims=True))
    mean = apply_coordinates(model.mean, info.coordinates, w)
    for t in (0, 50, 95):
        motion = (np.asarray(model.C) @ info.states[:, t]).reshape(model.frame_shape)
        frame = apply_coordinates(motion, info.coordinates, balanced) + mean
        np.testing.assert_allclose(video[t], np.clip(frame, 0, 1), atol=1e-9)
    # temporally coherent: the motion of the large frames is the small frames' (lag-1 correlation measured
    # 0.90-0.92 for both, within 0.003, over 3 seeds; bound 0.05)
    assert abs(temporal_correlation(video) - temporal_correlation(small)) < 0.05
    # no calm grid: the boundary zones move as much as the patches' interiors (temporal std ratio measured
    # 0.98-1.01 over 3 seeds; bounds 0.9-1.1). The baseline, the motion through the convex weights (a plain
    # average of independently moving pixels), measured 0.71-0.73, must fall below the bound
    motion = video.std(0).mean(-1)
    zones = w[..., 0] < 0.999
    assert zones.any() and 0.9 < motion[zones].mean() / motion[~zones].mean() < 1.1
    modes = np.stack([apply_coordinates(m, info.coordinates, w) for m in model.modes], -1).reshape(-1, model.state_dim)
    plain = np.clip((modes @ info.states).T.reshape(video.shape) + mean, 0, 1).std(0).mean(-1)
    assert plain[zones].mean() / plain[~zones].mean() < 0.85


def test_the_clip_size_needs_no_map(water):
    model = learn_dynamic_texture(water, state_dim=3)
    _, info = model.synthesize(3, size=(40, 40), rng=0, return_info=True)
    assert info.coordinates is None and info.map_info is None


# ---------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("kwargs, error, name", [
    ({"state_dim": 0}, ValueError, "state_dim"),
    ({"state_dim": -2}, ValueError, "state_dim"),
    ({"state_dim": 2.5}, TypeError, "state_dim"),
    ({"state_dim": True}, TypeError, "state_dim"),
    ({"state_dim": "many"}, ValueError, "state_dim"),
    ({"state_dim": 24}, ValueError, "state_dim"),  # T - 1 = 23 at most
    ({"noise_dim": -1}, ValueError, "noise_dim"),
    ({"noise_dim": 1.0}, TypeError, "noise_dim"),
    ({"state_dim": 2, "noise_dim": 3}, ValueError, "noise_dim"),
    ({"estimator": "ols"}, ValueError, "estimator"),
    ({"estimator": None}, TypeError, "estimator"),
])
def test_bad_options_name_the_parameter(kwargs, error, name):
    with pytest.raises(error, match=name):
        learn_dynamic_texture(wave(), **kwargs)
    with pytest.raises(error, match=name):
        dynamic_texture(wave(), 5, **kwargs)


@pytest.mark.parametrize("frames, error", [
    (wave()[:2], ValueError),  # fewer than 3 frames
    (np.zeros((5, 4, 4, 6)), ValueError),  # 6 channels
    (np.zeros((5, 4)), ValueError),  # no frame axis
    (np.full((5, 4, 4), np.nan), ValueError),
    (np.full((5, 4, 4), 3.0), ValueError),  # floats outside [0, 1]
    (np.zeros((5, 4, 4), np.int32), TypeError),
    (None, TypeError),
])
def test_bad_frames_name_the_parameter(frames, error):
    with pytest.raises(error, match="frames"):
        learn_dynamic_texture(frames)


@pytest.mark.parametrize("kwargs, error, name", [
    ({"n_frames": 0}, ValueError, "n_frames"),
    ({"n_frames": 2.0}, TypeError, "n_frames"),
    ({"size": (0, 5)}, ValueError, "size"),
    ({"size": "big"}, ValueError, "size"),
    ({"output_noise": "yes"}, TypeError, "output_noise"),
    ({"rng": "seed"}, TypeError, "rng"),
    ({"rng": -1}, ValueError, "rng"),
    ({"progress": "yes"}, TypeError, "progress"),
])
def test_bad_synthesis_options_name_the_parameter(kwargs, error, name):
    args = {"n_frames": 5, **kwargs}
    with pytest.raises(error, match=name):
        dynamic_texture(wave(), **args)
    model = learn_dynamic_texture(wave())
    with pytest.raises(error, match=name):
        model.synthesize(**args)


@settings(max_examples=25, deadline=None)
@given(value=st.one_of(st.text(max_size=8), st.floats(allow_nan=True), st.integers(-5, 0), st.none()))
def test_any_bad_state_dim_is_refused_with_its_name(value):
    if value == "auto":
        return
    with pytest.raises((TypeError, ValueError), match="state_dim"):
        learn_dynamic_texture(wave(), state_dim=value)


def test_memory_refused_before_allocating():
    clip = wave()
    with memory_limit(2**20, "a test budget"):  # 1 MiB
        with pytest.raises(ValueError, match="n_frames"):  # 10^6 frames of 12 x 16: 1.5 GB
            dynamic_texture(clip, 10**6, rng=0)
        model = learn_dynamic_texture(clip)
        with pytest.raises(ValueError, match="n_frames"):
            model.synthesize(10**6, rng=0)
        with pytest.raises(ValueError, match="size"):
            model.synthesize(2, size=4096, rng=0)
        # a clip too large to learn from: refused from its shape, before it is converted (a broadcast view
        # takes no memory; converting it would take 240 GB)
        huge = np.broadcast_to(np.zeros((1, 1, 1), np.uint8), (10**4, 1000, 1000))
        with pytest.raises(ValueError, match="frames"):
            learn_dynamic_texture(huge)


def test_the_model_can_be_built_by_hand():
    """A DynamicTexture from one's own matrices (a 1-D oscillator drawn into 2 x 2 frames) synthesises."""
    A = 0.9 * np.array([[np.cos(0.5), -np.sin(0.5)], [np.sin(0.5), np.cos(0.5)]])
    model = DynamicTexture(A=A, B=0.1 * np.eye(2), C=np.eye(4)[:, :2], mean=np.full((2, 2), 0.5), R=np.zeros((2, 2)),
                           x0=np.zeros(2), states=np.zeros((2, 3)), singular_values=np.ones(2),
                           eigenvalues=np.linalg.eigvals(A), stabilized=False, estimator="yule-walker",
                           frame_shape=(2, 2), dtype=np.dtype(np.float64))
    video = model.synthesize(50, rng=0)
    assert video.shape == (50, 2, 2) and np.all(video[:, 1] == 0.5)  # C leaves the second row to the mean
