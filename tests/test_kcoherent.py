"""Wei-Levoy synthesis with k-coherent candidates (texsynth.pixel._kcoherent: Ashikhmin 2001, Tong et al. 2002)."""

import numpy as np
import pytest

import texsynth
from texsynth import metrics
from texsynth.core.search import Search
from texsynth.pixel import Neighborhood

L2 = Neighborhood(levels=2)


def test_pixels_are_the_exemplar_pixels_named_by_the_coordinates(texture):
    ex = texture("jcjohnson/bread.png", 32)
    search = Search(candidates="k-coherent", k=2)
    out, info = texsynth.synthesize_pixels(ex, 40, neighborhood=L2, search=search, rng=0, return_info=True)
    rows, cols = info.coordinates[..., 0], info.coordinates[..., 1]
    np.testing.assert_array_equal(out, ex[rows, cols])  # every pixel is a copy of the one its source names
    assert info.candidates == "k-coherent" and info.coordinates.shape == (40, 40, 2)
    again = texsynth.synthesize_pixels(ex, 40, neighborhood=L2, search=search, rng=0)
    np.testing.assert_array_equal(out, again)


@pytest.mark.parametrize("name, bound", [
    # measured (seeds 0, 1): all 4.1-4.5 (bricks broken into mortar scraps), k-coherent 2.8-3.0 (bricks whole)
    ("embark/bricks.png", 3.6),
    # measured: all 48-69 (the output collapses to flat grey: Efros-Leung's "growing garbage"), k-coherent 1.5-1.9
    ("skimage/brick.png", 3.0),
])
def test_k_coherent_keeps_the_bricks_that_all_candidates_lose(texture, name, bound):
    """Completeness against a random-block mosaic: the fraction of exemplar patches the output misses."""
    ex = texture(name, 96)
    mosaic = metrics.completeness(metrics.mosaic_baseline(ex, 160, rng=0), ex)
    kcoherent = texsynth.synthesize_pixels(ex, 160, search=Search(candidates="k-coherent"), rng=0)
    ours = metrics.completeness(kcoherent, ex) / mosaic
    wei_levoy = metrics.completeness(texsynth.synthesize_pixels(ex, 160, rng=0), ex) / mosaic
    assert ours < bound < wei_levoy


def test_k_is_auto_one_and_candidates_auto_all(texture):
    ex = texture("jcjohnson/bread.png", 24)
    ashikhmin = texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="k-coherent"), rng=0)
    k1 = texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="k-coherent", k=1), rng=0)
    assert np.array_equal(ashikhmin, k1)
    assert np.array_equal(texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="auto"), rng=0),
                          texsynth.synthesize_pixels(ex, 20, neighborhood=L2, rng=0))


def test_k_coherent_bad_options(texture):
    ex = texture("jcjohnson/bread.png", 24)
    with pytest.raises(ValueError, match="candidates"):
        texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="coherent"))
    with pytest.raises(ValueError, match="order='scanline'"):
        texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="k-coherent"), order="independent")
    with pytest.raises(ValueError, match="k"):
        texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="k-coherent", k=0))
    with pytest.raises(ValueError, match="k=100000"):
        texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="k-coherent", k=100000))
    with pytest.raises(ValueError, match="tileable=True is not implemented"):
        texsynth.synthesize_pixels(ex, 20, neighborhood=L2, search=Search(candidates="k-coherent"), tileable=True)
