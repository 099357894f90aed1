"""Bundled sample textures."""

import pytest

from texsynth import data


def test_every_sample_loads_with_its_layout_and_attribution():
    attribution = data.path("bread").with_name("ATTRIBUTION.md").read_text()
    for name in data.names():
        image = data.load(name)
        assert image.dtype.kind == "f" and 0 <= image.min() and image.max() <= 1
        grey = data.KINDS[name].startswith("grey")
        assert image.ndim == (2 if grey else 3)
        assert f"| {name} |" in attribution
        assert image.std() > 0.05  # a real texture, not a flat placeholder


def test_unknown_name():
    with pytest.raises(ValueError, match="bread"):
        data.load("marble")
