"""Keyframe-guided stylisation of a clip (texsynth.stylize_video, Jamriška et al. 2019)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

import texsynth
from texsynth.core._validate import memory_limit
from texsynth.core.em import Schedule
from texsynth.core.flows import estimate_flows
from texsynth.metrics import flicker, texture_energy
from texsynth.video import stylize_video

SIZE, FRAMES = 48, 6
PALETTE = np.array([[0.10, 0.05, 0.20], [0.55, 0.12, 0.18], [0.93, 0.45, 0.15], [0.99, 0.86, 0.45]])


def paint(frame, palette=PALETTE):
    """A procedural painting of a frame: its luminance posterised into the palette, with outlines."""
    lum = ndimage.gaussian_filter(frame.mean(axis=-1), 1.0)
    label = np.digitize(lum, np.quantile(lum, [0.25, 0.5, 0.75]))
    out = palette[label].copy()
    out[ndimage.morphological_gradient(label, size=2) > 0] *= 0.4
    return out


@pytest.fixture(scope="module")
def clip():
    return texsynth.data.clip("waves", FRAMES, SIZE, rng=0)


@pytest.fixture(scope="module")
def flows(clip):
    return estimate_flows(clip)


@pytest.fixture(scope="module")
def one_key(clip, flows):
    """One keyframe (frame 0) carried through the clip, with and without the temporal guide."""
    key = paint(clip[0])
    with_guide = stylize_video(clip, {0: key}, flows=flows, rng=0, return_info=True)
    alone = stylize_video(clip, {0: key}, flows=flows, temporal_weight=0.0, rng=0)
    return key, with_guide, alone


def test_estimate_flows_recovers_a_translation():
    rng = np.random.default_rng(1)
    image = ndimage.gaussian_filter(rng.random((48, 48)), 2.0)
    frames = np.stack([image, ndimage.shift(image, (1.0, -2.0), mode="wrap")])
    flow = estimate_flows(frames)
    inner = flow[0, 8:-8, 8:-8]
    assert flow.shape == (1, 48, 48, 2)
    np.testing.assert_allclose(np.median(inner.reshape(-1, 2), axis=0), [1.0, -2.0], atol=0.15)


def test_output_shape_and_keyframe_reproduced(clip, one_key):
    key, (video, info), _ = one_key
    assert video.shape == (FRAMES, SIZE, SIZE, 3)
    assert np.array_equal(video[0], key)  # (c): the keyframe's output is its painting
    assert info.keyframes == (0,)
    assert info.flows.shape == (FRAMES - 1, SIZE, SIZE, 2)
    np.testing.assert_allclose(info.weights.sum(axis=1), 1.0)
    assert np.isfinite(info.errors[0, 1:]).all() and (info.errors[0, 0] == 0).all()
    assert info.syntheses == FRAMES - 1


def test_style_kept_far_below_a_noise_baseline(clip, one_key):
    """(a) every frame's texture energy against the painting, against two baselines computed here: the
    painting's own pixels shuffled (noise with its colours), and the painting of that frame made as the
    keyframe was (what a perfect stylisation would look like)."""
    key, (video, _), _ = one_key
    rng = np.random.default_rng(0)
    noise = rng.permutation(key.reshape(-1, 3)).reshape(key.shape)
    e_noise = texture_energy(noise, key)
    for t in range(1, FRAMES):
        e = texture_energy(video[t], key)
        e_ideal = texture_energy(paint(clip[t]), key)
        # measured (2026-11-28, one machine; not asserted): e 0.001-0.015 over frames 1-5, e_noise 0.087,
        # e_ideal 0.021-0.027 (the outputs copy the painting's own patches, so they score lower than a repainting)
        assert e < 0.3 * e_noise, (t, e, e_noise)
        assert e < 2.0 * e_ideal + 0.005, (t, e, e_ideal)


def test_temporal_guide_reduces_flicker(clip, flows, one_key):
    """(b) consecutive outputs change less along the motion with the temporal guide than each frame on its own
    (measured: 0.047 against 0.164, the clip itself 0.025; the margin asks for at least 15 % less)."""
    _, (video, _), alone = one_key
    assert flicker(video, flows) < 0.85 * flicker(alone, flows)


def test_follows_the_frames_not_just_the_painting(clip, one_key):
    """The last output is closer to its own frame's painting than the keyframe's painting is (the content moves
    with the frames; measured 0.28 against 0.34 mean absolute difference)."""
    key, (video, _), _ = one_key
    t = FRAMES - 1
    target = paint(clip[t])
    assert np.abs(video[t] - target).mean() < np.abs(key - target).mean()


def test_two_keyframes_blend(clip, flows):
    """(d) with two keyframes of very different palettes, the outputs move from the first's colours to the
    second's, and each keyframe is reproduced."""
    first = paint(clip[0])
    last = paint(clip[-1], palette=PALETTE[:, ::-1])  # blue-green palette
    video, info = stylize_video(clip, [(0, first), (FRAMES - 1, last)], flows=flows, rng=0, return_info=True)
    assert np.array_equal(video[0], first) and np.array_equal(video[-1], last)
    a, b = first.reshape(-1, 3).mean(0), last.reshape(-1, 3).mean(0)
    share = [float(np.dot(v.reshape(-1, 3).mean(0) - a, b - a) / np.dot(b - a, b - a)) for v in video]
    assert all(s1 < s2 + 0.02 for s1, s2 in zip(share, share[1:])), share
    mid = FRAMES // 2
    assert 0.2 < share[mid] < 0.8, share
    np.testing.assert_allclose(info.weights[mid], [(FRAMES - 1 - mid) / (FRAMES - 1), mid / (FRAMES - 1)])
    linear = stylize_video(clip, [(0, first), (FRAMES - 1, last)], flows=flows, rng=0, keyframe_blend="linear")
    assert np.isfinite(linear).all() and not np.array_equal(linear[mid], video[mid])


def test_keyframe_in_the_middle_goes_both_ways(clip, flows):
    key = paint(clip[2])
    video, info = stylize_video(clip, {2: key}, flows=flows, rng=0, return_info=True)
    assert np.array_equal(video[2], key)
    assert np.isfinite(info.errors[0]).all() and info.syntheses == FRAMES - 1
    e_noise = texture_energy(np.random.default_rng(0).permutation(key.reshape(-1, 3)).reshape(key.shape), key)
    assert texture_energy(video[0], key) < 0.3 * e_noise


def test_same_seed_same_clip(clip, flows):
    key = paint(clip[0])
    small = clip[:3]
    a = stylize_video(small, {0: key}, flows=flows[:2], rng=3)
    b = stylize_video(small, {0: key}, flows=flows[:2], rng=np.random.default_rng(3))
    assert np.array_equal(a, b)


def test_grey_painting_and_given_flows_keep_the_layout(clip):
    grey = paint(clip[0]).mean(axis=-1)
    still = np.zeros((2, SIZE, SIZE, 2))
    video = stylize_video(clip[:3], {0: grey}, flows=still, schedule=Schedule(max_iterations=1), rng=0)
    assert video.shape == (3, SIZE, SIZE)
    assert np.array_equal(video[0], grey)
    single = stylize_video(clip[:2], {1: grey.astype(np.float32)}, flows=still[:1],
                           schedule=Schedule(neighborhood_sizes=6, max_iterations=1), rng=0)
    assert single.dtype == np.float32 and single.shape == (2, SIZE, SIZE)  # float32 stays float32


def test_progress_counts_syntheses(clip, flows):
    seen = []
    stylize_video(clip[:3], {0: paint(clip[0])}, flows=flows[:2], schedule=Schedule(max_iterations=1), rng=0,
                  progress=lambda step, total, info: seen.append((step, total)))
    assert seen[-1] == (2, 2)


@pytest.mark.parametrize("keyframes, kwargs, error, words", [
    ({9: None}, {}, ValueError, "keyframes: frame index 9"),
    ({-1: None}, {}, ValueError, "keyframes: frame index -1"),
    ({0: np.zeros((10, 10, 3))}, {}, ValueError, "keyframes[0] has shape"),
    ("painting", {}, TypeError, "keyframes must be a dict"),
    ({}, {}, ValueError, "keyframes is empty"),
    ([(0, None), (0, None)], {}, ValueError, "painted twice"),
    ({0: None}, {"temporal_weight": -1.0}, ValueError, "temporal_weight"),
    ({0: None}, {"keyframe_blend": "poisson"}, ValueError, "keyframe_blend"),
    ({0: None}, {"flows": np.zeros((2, SIZE, SIZE, 2))}, ValueError, "flows"),
    ({0: None}, {"flows": "farneback"}, ValueError, "flows"),
    ({0: None}, {"schedule": Schedule(neighborhood_sizes=(64,))}, ValueError, "neighborhood_sizes"),
])
def test_bad_input_names_the_parameter(clip, keyframes, kwargs, error, words):
    key = paint(clip[0])
    if isinstance(keyframes, dict):
        keyframes = {k: key if v is None else v for k, v in keyframes.items()}
    elif isinstance(keyframes, list):
        keyframes = [(k, key) for k, _ in keyframes]
    with pytest.raises(error, match=words.replace("[", r"\[").replace("]", r"\]")):
        stylize_video(clip, keyframes, **kwargs)


def test_refuses_a_clip_too_large_for_memory(clip):
    with memory_limit(1e5, "a test's limit"), pytest.raises(ValueError, match="frames=.*pass a smaller frames"):
        stylize_video(clip, {0: paint(clip[0])})


@pytest.mark.parametrize("name", ["color_weight", "edge_weight", "positional_weight", "temporal_weight"])
def test_any_negative_or_nan_weight_is_refused_by_name(clip, name):
    hypothesis = pytest.importorskip("hypothesis")
    strategies = hypothesis.strategies

    @hypothesis.settings(max_examples=15, deadline=None)
    @hypothesis.given(strategies.one_of(strategies.floats(max_value=-1e-9), strategies.just(float("nan"))))
    def check(value):
        with pytest.raises(ValueError, match=name):
            stylize_video(clip[:2], {0: paint(clip[0])}, **{name: value})

    check()
