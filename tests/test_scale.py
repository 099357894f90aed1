"""The feature scale that the scale-aware defaults read (texsynth.core.scale)."""

import numpy as np

from texsynth.core.scale import feature_scale, octave_energy


def test_squares_of_a_known_size():
    # a mosaic of side x side squares of random grey values: its spectrum is the square's sinc^2,
    # which holds most of its energy at wavelengths of several sides (85 % below about 3-4 sides),
    # so the estimate lies between 2 and 5 sides and doubles when the side doubles
    rng = np.random.default_rng(0)
    scales = []
    for side in (4, 8, 16):
        image = np.kron(rng.random((512 // side, 512 // side)), np.ones((side, side)))
        scales.append(feature_scale(image))
        assert 2 * side <= scales[-1] <= 5 * side
    ratios = np.array(scales[1:]) / np.array(scales[:-1])
    assert np.all((ratios > 1.6) & (ratios < 2.5))


def test_real_textures_in_the_order_of_their_elements(texture):
    # letters (about 15 px) < pebbles (about 20 px) < bricks of a 192 px photo (about 50 px);
    # white noise (1 px) is the floor
    text = feature_scale(texture("lcv/text.pgm"))
    pebbles = feature_scale(texture("rohitrango/t4.png"))
    bricks = feature_scale(texture("rohitrango/t1.png"))
    noise = feature_scale(np.random.default_rng(0).random((192, 192)))
    assert noise < text < pebbles < bricks
    assert 10 <= text <= 25 and 12 <= pebbles <= 30 and 35 <= bricks <= 48


def test_flat_and_tiny_images():
    assert feature_scale(np.full((32, 32), 0.5)) == 4.0
    lams, shares = octave_energy(np.full((32, 32), 0.5))
    assert not shares.any() and lams[0] == 4.0
