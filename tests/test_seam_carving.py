"""Seam carving (texsynth.patch._seam_carving) on real photographs, against brute force where it is small."""

import numpy as np
import pytest
from skimage import data as skdata
from test_seams import all_seams  # every 8-connected seam of a small array

from texsynth.patch._seam_carving import (
    _Carver,
    _energy_at,
    carve_seams,
    gradient_energy,
)


def photo(step=4, name="astronaut"):
    """A real colour photograph (scikit-image's bundled samples), subsampled, as float64 in [0, 1]."""
    image = getattr(skdata, name)()[::step, ::step]
    return np.ascontiguousarray(image / 255.0)


def e1_reference(image):
    """The paper's eq. 1 written out pixel by pixel: central differences, halved, borders replicated."""
    h, w = image.shape[:2]
    e = np.zeros((h, w))
    for i in range(h):
        for j in range(w):
            dx = image[i, min(j + 1, w - 1)] - image[i, max(j - 1, 0)]
            dy = image[min(i + 1, h - 1), j] - image[max(i - 1, 0), j]
            e[i, j] = (np.abs(dx).sum() + np.abs(dy).sum()) / 2
    return e


def forward_path_cost(image, seam):
    """Rubinstein et al. 2008's forward energy of a vertical seam, pixel by pixel."""
    w = image.shape[1]

    def px(i, j):
        return image[i, min(max(j, 0), w - 1)]

    total = 0.0
    for i, j in enumerate(seam):
        total += np.abs(px(i, j + 1) - px(i, j - 1)).sum()  # C_U
        if i and seam[i - 1] == j - 1:  # from the upper left
            total += np.abs(px(i - 1, j) - px(i, j - 1)).sum()
        elif i and seam[i - 1] == j + 1:
            total += np.abs(px(i - 1, j) - px(i, j + 1)).sum()
    return total


def is_seam(seam, length, across):
    return seam.shape == (length,) and seam.min() >= 0 and seam.max() < across and np.all(np.abs(np.diff(seam)) <= 1)


# --------------------------------------------------------------------------- the energy and the optimal seam


def test_the_energy_is_eq_1_and_the_local_update_is_the_full_recomputation():
    image = photo(16)[:20, :24]
    assert np.allclose(gradient_energy(image), e1_reference(image))
    rows, cols = np.nonzero(np.ones((20, 24), bool))
    assert np.array_equal(_energy_at(image, rows, cols), gradient_energy(image).ravel())
    # after 40 removals in both directions the kept energy is still exactly the recomputed one
    state = _Carver(photo(4)[:96, :128], None, "backward")
    for direction in ("vertical", "horizontal", "vertical", "vertical") * 10:
        seam, _ = state.seam(direction)
        state = state.removed(direction, seam)
    assert state.shape == (86, 98)
    assert np.array_equal(state.energy, gradient_energy(state.image))


@pytest.mark.parametrize("energy", ["backward", "forward"])
@pytest.mark.parametrize("where", [(200, 220), (100, 300), (330, 160)])
def test_the_removed_seam_is_the_cheapest_of_all_seams(energy, where):
    # a 6 x 7 crop of a photograph: all 8-connected seams enumerated (about 1500)
    image = photo(1)[where[0]:where[0] + 6, where[1]:where[1] + 7]
    out, info = carve_seams(image, (6, 6), energy=energy, return_info=True)
    direction, seam = info.seams[0]
    assert direction == "vertical" and is_seam(seam, 6, 7)
    if energy == "backward":
        e = e1_reference(image)
        costs = [e[np.arange(6), s].sum() for s in all_seams(6, 7)]
        chosen = e[np.arange(6), seam].sum()
    else:
        costs = [forward_path_cost(image, s) for s in all_seams(6, 7)]
        chosen = forward_path_cost(image, seam)
    assert chosen == pytest.approx(min(costs), abs=1e-9)
    assert info.costs[0] == pytest.approx(min(costs), abs=1e-9)
    # the output is the input without the seam's pixels
    keep = np.ones((6, 7), bool)
    keep[np.arange(6), seam] = False
    assert np.array_equal(out, image[keep].reshape(6, 6, 3))
    # a horizontal seam is the vertical seam of the transposed image
    out_h, info_h = carve_seams(image.transpose(1, 0, 2), (6, 6), energy=energy, return_info=True)
    assert info_h.seams[0][0] == "horizontal" and np.array_equal(info_h.seams[0][1], seam)
    assert np.array_equal(out_h, out.transpose(1, 0, 2))


def test_every_removed_seam_is_one_pixel_per_row_8_connected_and_the_output_is_what_is_left():
    image = photo(4)  # 128 x 128
    out, info = carve_seams(image, (110, 100), order="alternate", return_info=True)
    assert out.shape == (110, 100, 3) and info.n_removed == (18, 28) and len(info.seams) == 46
    shape = [128, 128]
    for direction, seam in info.seams:
        length, across = (shape[0], shape[1]) if direction == "vertical" else (shape[1], shape[0])
        assert is_seam(seam, length, across)
        shape[1 if direction == "vertical" else 0] -= 1
    # every output pixel is the input pixel its source map names, each input pixel at most once
    src = info.source
    assert np.array_equal(out, image[src[..., 0], src[..., 1]])
    assert np.unique(src[..., 0] * 128 + src[..., 1]).size == 110 * 100
    assert not info.inserted.any()
    # carving takes the low-energy pixels: the removed ones have less energy than the kept ones
    e = gradient_energy(image)
    kept = np.zeros((128, 128), bool)
    kept[src[..., 0], src[..., 1]] = True
    assert e[~kept].mean() < 0.6 * e[kept].mean()


def test_the_optimal_order_costs_no_more_than_any_fixed_order():
    image = photo(8, "chelsea")  # 38 x 57 cat photograph
    target = (30, 47)
    totals = {}
    for order in ("optimal", "alternate", "vertical-first", "horizontal-first"):
        out, info = carve_seams(image, target, order=order, return_info=True)
        assert out.shape == target + (3,) and info.n_removed == (8, 10)
        totals[order] = info.costs.sum()
        if order == "optimal":
            # the replayed order costs exactly the transport map's T(r, c)
            assert info.transport_map.shape == (9, 11)
            assert info.costs.sum() == pytest.approx(info.transport_map[-1, -1], rel=1e-12)
    for order in ("alternate", "vertical-first", "horizontal-first"):
        assert totals["optimal"] <= totals[order] + 1e-9, totals
    assert totals["optimal"] < max(totals.values())


# --------------------------------------------------------------------------- enlarging


def test_insertion_followed_by_removal_of_the_same_seams_gives_the_original():
    image = photo(4, "coffee")  # 100 x 150
    k = 30
    out, info = carve_seams(image, (100, 150 + k), return_info=True)
    assert out.shape == (100, 180, 3) and info.n_inserted == (0, k)
    ins = info.inserted
    assert np.all(ins.sum(axis=1) == k)  # k new pixels in every row: k vertical seams
    # removing the inserted pixels gives the input back, bit for bit
    assert np.array_equal(out[~ins].reshape(100, 150, 3), image)
    # each inserted pixel is the mean of the seam pixel it follows and that pixel's right neighbour
    r, c = np.nonzero(ins)
    sr, sc = info.source[r, c, 0], info.source[r, c, 1]
    assert np.array_equal(out[r, c], (image[sr, sc] + image[sr, np.minimum(sc + 1, 149)]) / 2)
    # and the seams inserted are the k seams that removal takes first
    _, shrink = carve_seams(image, (100, 150 - k), return_info=True)
    removed = np.ones((100, 150), bool)
    removed[shrink.source[..., 0], shrink.source[..., 1]] = False
    duplicated = np.zeros((100, 150), bool)
    duplicated[sr, sc] = True
    assert np.array_equal(removed, duplicated)


def test_large_enlargements_go_in_steps_and_both_directions_work():
    image = photo(8)  # 64 x 64
    out, info = carve_seams(image, (90, 150), return_info=True)
    assert out.shape == (90, 150, 3) and info.n_inserted == (26, 86)
    assert 0 <= out.min() and out.max() <= 1
    assert np.array_equal(out[~info.inserted], image[info.source[~info.inserted][:, 0],
                                                     info.source[~info.inserted][:, 1]])
    mixed = carve_seams(image, (50, 80))
    assert mixed.shape == (50, 80, 3)


def test_a_larger_size_without_enlarging_is_refused_naming_size_and_the_fix():
    with pytest.raises(ValueError, match=r"size .* enlarge=True"):
        carve_seams(photo(8), (64, 70), enlarge=False)


# --------------------------------------------------------------------------- object removal and protection


def test_object_removal_removes_every_masked_pixel_and_restores_the_size():
    image = photo(4)  # 128 x 128 astronaut
    mask = np.zeros((128, 128), bool)
    mask[20:70, 90:110] = True  # part of the flag and the background, 20 columns wide
    small, info = carve_seams(image, remove_mask=mask, enlarge=False, return_info=True)
    src = info.source
    assert not mask[src[..., 0], src[..., 1]].any()  # no masked pixel survives
    assert small.shape[0] == 128 and 108 <= small.shape[1] < 128 and info.removal_size == small.shape[:2]
    assert info.n_removed == (0, 128 - small.shape[1])
    # restored to the input's size by inserting seams: still no masked pixel, inserted ones included
    full, info = carve_seams(image, remove_mask=mask, return_info=True)
    assert full.shape == image.shape and info.n_inserted == (0, 128 - small.shape[1])
    assert not mask[info.source[..., 0], info.source[..., 1]].any()
    # a wide object is removed with horizontal seams
    wide = np.zeros((128, 128), bool)
    wide[100:110, 10:80] = True
    _, info = carve_seams(image, remove_mask=wide, enlarge=False, return_info=True)
    assert info.n_removed[1] == 0 and info.n_removed[0] >= 10
    assert not wide[info.source[..., 0], info.source[..., 1]].any()


def test_protected_pixels_all_survive_while_unprotected_carving_takes_them():
    image = photo(4)
    protect = np.zeros((128, 128), bool)
    protect[:, 30:60] = True  # a band with the astronaut's face and shoulder
    e = gradient_energy(image)
    protect &= e < np.median(e)  # ... its low-energy pixels, which carving would take first
    _, info = carve_seams(image, (128, 88), protect_mask=protect, return_info=True)
    kept = np.zeros((128, 128), bool)
    kept[info.source[..., 0], info.source[..., 1]] = True
    assert kept[protect].all()
    _, plain = carve_seams(image, (128, 88), return_info=True)
    kept_plain = np.zeros((128, 128), bool)
    kept_plain[plain.source[..., 0], plain.source[..., 1]] = True
    assert not kept_plain[protect].all()
    # the optimal order and the forward energy honour the masks too (a block that seams can go round)
    block = np.zeros((48, 64), bool)
    block[10:30, 20:45] = True
    _, info = carve_seams(image[:48, :64], (40, 50), energy="forward", protect_mask=block, return_info=True)
    kept = np.zeros((48, 64), bool)
    kept[info.source[..., 0], info.source[..., 1]] = True
    assert kept[block].all()


# --------------------------------------------------------------------------- conventions and bad input


def test_layout_dtype_progress_and_no_op():
    grey = np.asarray(skdata.camera()[::8, ::8])  # uint8 grey
    out = carve_seams(grey, (60, 50))
    assert out.shape == (60, 50) and out.dtype == np.float64
    f32 = photo(8).astype(np.float32)
    assert carve_seams(f32, (60, 60)).dtype == np.float32
    assert np.array_equal(carve_seams(photo(8)), photo(8))
    steps = []
    carve_seams(photo(8), (64, 60), progress=lambda step, total, info: steps.append((step, total)))
    assert steps[-1] == (4, 4)
    custom = carve_seams(photo(8), (64, 60), energy=lambda im: np.ones(im.shape[:2]))
    assert custom.shape == (64, 60, 3)


@pytest.mark.parametrize("kwargs, error, words", [
    ({"size": (0, 10)}, ValueError, "size"),
    ({"energy": "sobel"}, ValueError, "energy"),
    ({"order": "random"}, ValueError, "order"),
    ({"enlarge": "no"}, TypeError, "enlarge"),
    ({"remove_mask": np.zeros((5, 5), bool)}, ValueError, "remove_mask"),
    ({"protect_mask": "mask"}, TypeError, "protect_mask"),
    ({"remove_mask": np.eye(64, dtype=bool), "protect_mask": np.eye(64, dtype=bool)}, ValueError, "both"),
    ({"energy": lambda im: np.ones(3)}, ValueError, "energy"),
    ({"size": (10**6, 10**6)}, ValueError, "size"),
])
def test_bad_input_names_the_parameter(kwargs, error, words):
    args = {"size": (60, 60)}
    args.update(kwargs)
    with pytest.raises(error, match=words):
        carve_seams(photo(8), **args)
