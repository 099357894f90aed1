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


def test_bricks_hole_has_its_hole_in_the_alpha_channel():
    image = data.load("bricks_hole")
    assert image.shape == (175, 175, 4)
    hole = image[..., 3] < 0.5
    assert 0.05 < hole.mean() < 0.3  # a round hole, well inside the image
    rows, cols = hole.nonzero()
    assert rows.min() > 0 and cols.min() > 0 and rows.max() < 174 and cols.max() < 174
