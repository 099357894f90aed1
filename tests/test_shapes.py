"""The test surfaces of texsynth.surface (texsynth.surface._shapes): sphere, torus, bumpy and the scanned bunny."""

import tracemalloc

import numpy as np
import pytest

from texsynth.core._validate import memory_limit
from texsynth.surface import as_mesh, bumpy, scanned_mesh, sphere, torus


# ---------------------------------------------------------------------------- shapes
def _euler(mesh):
    return len(mesh.vertices) - len(mesh.edges) + len(mesh.faces)


def _signed_volume(mesh):
    v = mesh.vertices[mesh.faces]
    return np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6


@pytest.mark.parametrize("n", [12, 42, 100, 2562])
def test_sphere_is_a_closed_outward_genus_zero_surface(n):
    mesh = as_mesh(sphere(n, radius=2.0))
    assert _euler(mesh) == 2 and np.all(mesh.face_adjacency >= 0)
    np.testing.assert_allclose(np.linalg.norm(mesh.vertices, axis=1), 2.0)
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    assert np.all(np.sum(centroids * mesh.face_normals, axis=1) > 0)  # every face normal points away from the centre
    assert 0.6 * n <= len(mesh.vertices) <= 1.5 * n  # "about n_vertices"


def test_sphere_converges_to_the_ball():
    # an inscribed polyhedron: its volume approaches 4/3 pi r^3 from below as it is refined
    coarse, fine = _signed_volume(sphere(162)), _signed_volume(sphere(10242))
    assert coarse < fine < 4 / 3 * np.pi
    assert fine == pytest.approx(4 / 3 * np.pi, rel=2e-3)


def test_torus_is_a_closed_outward_genus_one_surface():
    mesh = as_mesh(torus(3000, major_radius=2.0, minor_radius=0.5))
    assert _euler(mesh) == 0 and np.all(mesh.face_adjacency >= 0)
    assert 0.8 * 3000 <= len(mesh.vertices) <= 1.2 * 3000
    # outward: away from the nearest point of the tube's core circle
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    core = centroids * [1, 1, 0]
    core = 2.0 * core / np.linalg.norm(core, axis=1, keepdims=True)
    assert np.all(np.sum((centroids - core) * mesh.face_normals, axis=1) > 0)
    assert _signed_volume(mesh) == pytest.approx(2 * np.pi ** 2 * 2.0 * 0.5 ** 2, rel=1e-2)


def test_bumpy_is_deterministic_closed_and_bumpy():
    a, b, c = bumpy(642, rng=3), bumpy(642, rng=3), bumpy(642, rng=4)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert not np.array_equal(a.vertices, c.vertices)
    as_mesh(a)
    assert _euler(a) == 2 and _signed_volume(a) > 0
    r = np.linalg.norm(a.vertices, axis=1)
    assert r.min() == pytest.approx(0.85, abs=0.01) or r.max() == pytest.approx(1.15, abs=0.01)  # amplitude 0.15
    assert 0.85 - 1e-9 <= r.min() and r.max() <= 1.15 + 1e-9
    flat = bumpy(642, amplitude=0.0, rng=3)
    np.testing.assert_allclose(np.linalg.norm(flat.vertices, axis=1), 1.0)


@pytest.mark.parametrize("call, error, message", [
    (lambda: sphere(0), ValueError, "n_vertices must be an integer >= 1"),
    (lambda: sphere(10.5), TypeError, "n_vertices must be an integer"),
    (lambda: sphere(radius=-1), ValueError, "radius must be a finite number > 0"),
    (lambda: torus(major_radius=1, minor_radius=1), ValueError, r"minor_radius \(1.0\) must be less than major_radius"),
    (lambda: bumpy(amplitude=1.0), ValueError, r"amplitude must lie in \[0.0, 1.0\)"),
    (lambda: bumpy(rng="seed"), TypeError, "rng must be None, an int seed"),
    (lambda: scanned_mesh("dragon"), ValueError, r"name must be one of \['bunny'\]"),
])
def test_shapes_refuse_bad_parameters(call, error, message):
    with pytest.raises(error, match=message):
        call()


@pytest.mark.parametrize("shape", [sphere, torus, bumpy])
def test_a_shape_that_cannot_fit_is_refused_before_allocating(shape):
    # 1 MB allowed: 10^5 vertices need tens of MB; refused with the figures, before anything of that size
    tracemalloc.start()
    try:
        with memory_limit(1e6, "a test's limit"), pytest.raises(
                ValueError, match=r"n_vertices=100000 needs about 0\.\d GiB .* more than the 0\.0 GiB of a test's "
                                  r"limit; pass a smaller n_vertices"):
            shape(100000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1e6


@pytest.mark.parametrize("shape", [sphere, torus, bumpy])
def test_the_memory_estimate_of_a_shape_bounds_its_peak(shape, monkeypatch):
    import texsynth.surface._shapes as shapes

    estimates = []
    monkeypatch.setattr(shapes, "check_memory", lambda nbytes, *args, **kwargs: estimates.append(nbytes))
    shape(3000)  # warm up: caches and imports are not the shape's memory
    tracemalloc.start()
    try:
        shape(20000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert estimates[-1] >= peak


# ---------------------------------------------------------------------------- the scanned mesh
def test_the_scanned_bunny_is_a_valid_closed_mesh():
    bunny = as_mesh(scanned_mesh())
    assert bunny.vertices.shape == (34835, 3) and bunny.faces.shape == (69666, 3)
    assert _euler(bunny) == 2 and np.all(bunny.face_adjacency >= 0) and _signed_volume(bunny) > 0
    assert np.linalg.norm(bunny.vertices, axis=1).max() == pytest.approx(1.0)
    np.testing.assert_allclose(bunny.bounds.sum(axis=0), 0, atol=1e-12)  # centred on its bounding box
    extent = np.ptp(bunny.vertices, axis=0)
    assert extent[2] > 0.9 * extent.max()  # z up: the bunny with its ears is about as tall as it is long


def test_scanned_mesh_names_the_extra_when_the_package_is_missing(monkeypatch):
    import importlib.util

    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None)
    with pytest.raises(ModuleNotFoundError, match=r"visvis package, which is not installed; python -m pip install .*'visvis>=1.14'"):
        scanned_mesh()
