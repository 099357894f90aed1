"""Image conversion and argument checks at the public boundary."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from texsynth.core._validate import as_float_array, as_image, as_rng, as_size, check_in_range, check_positive_float, check_positive_int, restore_channels, with_channels


def test_uint8_and_uint16_scale_to_unit_range():
    assert np.array_equal(as_float_array(np.array([0, 51, 255], np.uint8)), [0.0, 0.2, 1.0])
    assert np.array_equal(as_float_array(np.array([0, 65535], np.uint16)), [0.0, 1.0])
    assert as_float_array(np.array([True, False])).tolist() == [1.0, 0.0]


def test_float32_stays_float32_everything_else_float64():
    assert as_float_array(np.zeros(3, np.float32)).dtype == np.float32
    for dtype in (np.uint8, np.uint16, np.bool_, np.float16, np.float64):
        assert as_float_array(np.zeros(3, dtype)).dtype == np.float64


def test_conversion_does_not_alias_the_input():
    a = np.full((2, 2), 0.5)
    b = as_float_array(a)
    b[0, 0] = 0.0
    assert a[0, 0] == 0.5


@pytest.mark.parametrize("bad, match", [
    (np.array([np.nan]), "NaN"),
    (np.array([np.inf]), "NaN or infinite"),
    (np.array([0.0, 255.0]), "divide by 255"),
    (np.array([-0.5, 0.5]), r"\[0, 1\]"),
    (np.zeros((0, 3)), "empty"),
])
def test_bad_values_raise_valueerror_naming_the_parameter(bad, match):
    with pytest.raises(ValueError, match=match) as info:
        as_float_array(bad, "exemplar")
    assert "exemplar" in str(info.value)


@pytest.mark.parametrize("dtype", [np.int64, np.int8, np.complex128, object])
def test_unsupported_dtypes_raise_typeerror_with_the_fix(dtype):
    with pytest.raises(TypeError, match="uint8"):
        as_float_array(np.zeros(3, dtype=dtype), "exemplar")


@pytest.mark.parametrize("shape", [(5,), (2, 3, 5), (2, 3, 0), (1, 2, 3, 4, 5)])
def test_wrong_shapes_raise(shape):
    with pytest.raises(ValueError, match="image must have shape"):
        as_image(np.zeros(shape, np.uint8))


def test_volumes_and_min_size():
    assert as_image(np.zeros((2, 3, 4, 3), np.uint8), spatial_dims=3).shape == (2, 3, 4, 3)
    with pytest.raises(ValueError, match="at least 4 pixels"):
        as_image(np.zeros((3, 8)), min_size=4)


def test_channel_layout_round_trip():
    grey = np.zeros((3, 4))
    arr, was_grey = with_channels(grey)
    assert arr.shape == (3, 4, 1) and was_grey
    assert restore_channels(arr, was_grey).shape == (3, 4)
    colour = np.zeros((3, 4, 3))
    arr, was_grey = with_channels(colour)
    assert arr is colour and not was_grey


def test_rng_and_size_checks():
    assert as_rng(3).random() == as_rng(3).random()
    gen = np.random.default_rng(1)
    assert as_rng(gen) is gen
    with pytest.raises(TypeError, match="rng"):
        as_rng("seed")
    with pytest.raises(ValueError, match="rng"):
        as_rng(-1)
    assert as_size(7, ndim=3) == (7, 7, 7)
    for bad in [(0, 5), (3,), (2.5, 3), -1]:
        with pytest.raises((ValueError, TypeError), match="size"):
            as_size(bad)
    with pytest.raises(ValueError, match="octaves must be an integer >= 1"):
        check_positive_int(0, "octaves")
    with pytest.raises(ValueError, match="sharpness must be a finite number > 0"):
        check_positive_float(0.0, "sharpness")
    with pytest.raises(ValueError, match=r"alpha must lie in \[0, 1\]"):
        check_in_range(1.5, "alpha", 0, 1)


_dtypes = st.sampled_from([np.uint8, np.uint16, np.bool_, np.float32, np.float64])
_shapes = st.one_of(
    hnp.array_shapes(min_dims=2, max_dims=2, min_side=1, max_side=6),
    st.tuples(st.integers(1, 6), st.integers(1, 6), st.integers(1, 4)),
)


@settings(max_examples=25, deadline=None)
@given(data=st.data(), dtype=_dtypes, shape=_shapes)
def test_conversion_property(data, dtype, shape):
    if np.issubdtype(dtype, np.floating):
        elements = st.floats(0, 1, width=32 if dtype == np.float32 else 64)
    else:
        elements = None
    arr = data.draw(hnp.arrays(dtype, shape, elements=elements))
    out = as_image(arr)
    assert out.shape == arr.shape
    assert out.dtype == (np.float32 if dtype == np.float32 else np.float64)
    assert out.min() >= 0 and out.max() <= 1
    if dtype == np.uint8:
        assert np.array_equal(np.round(out * 255).astype(np.uint8), arr)


def test_bool_options_accept_only_bools():
    import texsynth

    ex = np.random.default_rng(0).random((24, 24))
    with pytest.raises(TypeError, match="tileable must be True or False"):
        texsynth.patchwork(ex, 24, grid_spacing=8, tileable="no")
    with pytest.raises(TypeError, match="tileable must be True or False"):
        texsynth.optimize_texture(ex, 24, schedule=texsynth.optimization.Schedule(neighborhood_sizes=(8,), levels=1),
                                  tileable="no")
    with pytest.raises(TypeError, match="falloff must be True or False"):
        texsynth.optimize_texture(ex, 24, schedule=texsynth.optimization.Schedule(neighborhood_sizes=(8,), levels=1),
                                  terms=texsynth.optimization.Terms(falloff=1))


def test_thread_limits_of_the_user_are_respected():
    from threadpoolctl import threadpool_limits

    from texsynth.core._validate import max_threads

    before = max_threads()  # the libraries are found here, once; their limits are read at every call
    with threadpool_limits(1):
        assert max_threads() == 1
    assert max_threads() == before
    assert 1 <= before <= (__import__("os").cpu_count() or 1)


def test_under_an_address_space_limit_the_memory_available_is_what_is_left_of_it(monkeypatch):
    # ``ulimit -v`` caps the process's whole address space, the part it already uses included: a check
    # against the whole cap let work through that then ran out of memory (N11)
    import resource

    from texsynth.core._validate import available_memory

    with open("/proc/self/status") as f:
        in_use = next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:"))
    cap = in_use + 2**30
    monkeypatch.setattr(resource, "getrlimit", lambda which: (cap, resource.RLIM_INFINITY)
                        if which == resource.RLIMIT_AS else (resource.RLIM_INFINITY,) * 2)
    left = available_memory()
    assert left <= 2**30 + 2**26  # about what is left (the process may have grown a little since)
    assert left >= 0


def test_a_file_name_or_path_given_for_an_image_is_read(tmp_path):
    # notebooks pass paths: a str used to be a TypeError, a pathlib.Path a confusing shape error
    from pathlib import Path

    import texsynth
    from texsynth import data
    from texsynth.io import load_frames, load_image, save_frames, save_image

    image = data.load("bread")[:40, :40]
    path = save_image(tmp_path / "bread.png", image)
    for given in (str(path), Path(path)):
        assert np.array_equal(as_image(given, "exemplar"), load_image(path))
    assert np.array_equal(texsynth.quilt(str(path), 48, block=12, rng=0),
                          texsynth.quilt(load_image(path), 48, block=12, rng=0))
    assert np.array_equal(texsynth.patchwork(Path(path), 48, rng=0), texsynth.patchwork(load_image(path), 48, rng=0))
    clip = np.stack([data.load("metal")[:16, t:t + 16] for t in range(3)])
    gif = save_frames(tmp_path / "clip.gif", clip)
    assert np.array_equal(as_image(gif, "frames", spatial_dims=3), load_frames(gif))
    with pytest.raises(FileNotFoundError):
        texsynth.quilt(str(tmp_path / "missing.png"), 48)
    (tmp_path / "notes.txt").write_text("not an image")
    with pytest.raises(ValueError, match="notes.txt"):
        as_image(tmp_path / "notes.txt", "exemplar")
