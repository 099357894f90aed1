"""The assertion helpers of texsynth.testing: argument checks and switched-off bounds.

How the assertion ranks real textures is tested with the metrics, in tests/test_metrics.py.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from texsynth import metrics
from texsynth.testing import TextureAssertionError, assert_texture_like, relative_scores

EX = np.random.default_rng(0).random((20, 20))
BOUNDS = ("max_energy", "max_completeness", "max_spectrum", "max_copy")


def test_relative_scores_needs_a_report_with_baselines():
    with pytest.raises(TypeError, match="report must be a texsynth.metrics.TextureReport.*NoneType"):
        relative_scores(None)
    with pytest.raises(TypeError, match="report must be"):
        relative_scores({"values": {}, "reference": {}})
    bare = metrics.texture_report(EX, EX, patch_size=4, with_baselines=False)
    with pytest.raises(ValueError, match="no 'tiled' baseline.*with_baselines=True"):
        relative_scores(bare)
    with pytest.raises(ValueError, match="report.values lacks"):
        relative_scores(metrics.TextureReport(values={"energy": 0.0}, reference={}))
    full = metrics.texture_report(EX, EX, patch_size=4)
    assert relative_scores(full) == {"energy": 0.0, "completeness": 0.0, "spectrum": 0.0,
                                     "verbatim_copy": full.values["verbatim_copy"]}


@pytest.mark.parametrize("bound", BOUNDS)
@pytest.mark.parametrize("value, error", [(float("nan"), ValueError), (-0.1, ValueError), ("0.5", TypeError),
                                          (True, TypeError), (None, TypeError)])
def test_bounds_are_checked_before_anything_is_computed(bound, value, error):
    # the images are bad too: the bound is reported first, so nothing was measured
    with pytest.raises(error, match=bound):
        assert_texture_like(None, None, **{bound: value})


def test_an_infinite_bound_switches_its_check_off():
    noise = metrics.noise_baseline(EX, 24, rng=0)
    with pytest.raises(TextureAssertionError, match="energy"):
        assert_texture_like(noise, EX, patch_size=4)
    off = dict.fromkeys(BOUNDS, float("inf"))
    report = assert_texture_like(noise, EX, patch_size=4, **off)
    assert report.values["energy"] > 0
    # a zero bound is allowed: it asks for a perfect score (the exemplar itself has one, except copying)
    assert_texture_like(EX, EX, patch_size=4, max_energy=0, max_completeness=0, max_spectrum=0, max_copy=np.inf)


_NOT_BOUNDS = st.one_of(st.none(), st.booleans(), st.text(max_size=3), st.floats(max_value=-1e-9),
                        st.just(float("nan")), st.lists(st.floats(0, 1), max_size=2))
_NOT_REPORTS = st.one_of(st.none(), st.integers(), st.text(max_size=3), st.dictionaries(st.text(max_size=2), st.floats()),
                         st.just(metrics.TextureReport(values={}, reference={})))


@pytest.mark.parametrize("name", BOUNDS + ("report", "output", "exemplar", "patch_size", "rng"))
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_bad_input_is_refused_naming_the_parameter(name, data):
    if name == "report":
        with pytest.raises((TypeError, ValueError), match="report"):
            relative_scores(data.draw(_NOT_REPORTS, label=name))
        return
    strategies = {
        "output": st.one_of(st.none(), st.text(max_size=3), st.just(np.full((20, 20), np.nan)), st.just(np.zeros(5))),
        "patch_size": st.one_of(st.none(), st.booleans(), st.floats(), st.integers(max_value=0), st.integers(21, 10**6)),
        "rng": st.one_of(st.integers(max_value=-1), st.floats(), st.text(max_size=3), st.booleans()),
    }
    strategies["exemplar"] = strategies["output"]
    value = data.draw(strategies.get(name, _NOT_BOUNDS), label=name)
    kwargs = {"patch_size": 4, name: value}
    output, exemplar = kwargs.pop("output", EX), kwargs.pop("exemplar", EX)
    with pytest.raises((TypeError, ValueError)) as info:
        assert_texture_like(output, exemplar, **kwargs)
    assert name in str(info.value)
