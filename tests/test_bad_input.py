"""Bad input over every public function: refused at once, naming the parameter, before anything is allocated."""

import subprocess
import sys
import textwrap

import pytest

# Every public function that makes something of a given size, called with a size that cannot fit
# (10^10 pixels), in a child process whose address space is capped at 4 GiB: a missing pre-flight
# check fails there with MemoryError (or is killed) instead of swapping the machine.
HUGE = {
    "synthesize_pixels": "texsynth.synthesize_pixels(ex, (100000, 100000), neighborhood=texsynth.Neighborhood(levels=2), "
                         "rng=0)",
    "synthesize_pixels independent": "texsynth.synthesize_pixels(ex, (100000, 100000), order='independent', rng=0)",
    "mix_textures": "texsynth.mix_textures([ex, ex], (100000, 100000), weights=[1.0, 2.0], rng=0)",
    "synthesize_solid": "texsynth.synthesize_solid(ex, 5000, rng=0)",
    "synthesize_controlled": "texsynth.synthesize_controlled(ex, (100000, 100000), rng=0)",
    "optimize_texture": "texsynth.optimize_texture(ex, (100000, 100000), rng=0)",
    "uncrop": "texsynth.uncrop(ex, (100000, 100000), rng=0)",
    "interpolate_textures": "texsynth.interpolate_textures(ex, ex, 0.5, size=(100000, 100000), rng=0)",
    "patchwork": "texsynth.patchwork(ex, (100000, 100000), grid_spacing=16, rng=0)",
    "patchwork default grid": "texsynth.patchwork(ex, (100000, 100000), rng=0)",
    "graphcut_texture": "texsynth.graphcut_texture(ex, (100000, 100000), rng=0)",
    "carve_seams": "texsynth.carve_seams(ex, (100000, 100000))",
    "wang_texture": "texsynth.wang_texture(ex, (100000, 100000), tile=16, rng=0)",
    "patchwork_video": "texsynth.patchwork_video(np.stack([ex] * 3), (30000, 30000), 40, grid_spacing=16, rng=0)",
    "voronoi_weights": "texsynth.patch.voronoi_weights((100000, 100000), grid_spacing=16, rng=0)",
    "heeger_bergen": "texsynth.heeger_bergen(ex, (100000, 100000), rng=0)",
    "portilla_simoncelli": "texsynth.portilla_simoncelli(ex, (100000, 100000), rng=0)",
    "random_phase_noise": "texsynth.random_phase_noise(ex, (100000, 100000), rng=0)",
    "tile_and_blend": "texsynth.tile_and_blend(ex, (100000, 100000), rng=0)",
    "tile_and_blend_at": "texsynth.tile_and_blend_at(ex, np.broadcast_to(np.int8(0), (100000, 100000)), 0, rng=0)",
    "flows.rotation": "texsynth.core.flows.rotation((100000, 100000), 0.1)",
    "transition_alpha_map": "texsynth.optimization.transition_alpha_map((100000, 100000))",
    "noise_baseline": "texsynth.metrics.noise_baseline(ex, (100000, 100000), rng=0)",
    "accumulate": "texsynth.core.neighborhood.accumulate(np.zeros((1, 2, 2, 3)), [[0, 0]], (100000, 100000))",
    "grid_centers": "texsynth.core.neighborhood.grid_centers((10**7, 10**7), 4, 1)",
    "gaussian_falloff": "texsynth.core.neighborhood.gaussian_falloff(10**6)",
    "SteerablePyramid": "texsynth.core.pyramid.SteerablePyramid((100000, 100000))",
    "mosaic_baseline": "texsynth.metrics.mosaic_baseline(ex, (100000, 100000), rng=0)",
    "tiled_baseline": "texsynth.metrics.tiled_baseline(ex, (100000, 100000))",
    "perlin": "texsynth.procedural.perlin((100000, 100000))",
    "turbulence": "texsynth.procedural.turbulence((100000, 100000))",
    "marble": "texsynth.procedural.marble((100000, 100000))",
    "reaction_diffusion": "texsynth.procedural.reaction_diffusion((100000, 100000), steps=1)",
    "gray_scott": "texsynth.procedural.gray_scott((100000, 100000), steps=1)",
    "sphere": "texsynth.surface.sphere(10**9)",
    "torus": "texsynth.surface.torus(10**9)",
    "bumpy": "texsynth.surface.bumpy(10**9, rng=0)",
    "default_splotch": "texsynth.surface.default_splotch((100000, 100000), rng=0)",
    "progressive_surface": "texsynth.surface.progressive_surface(texsynth.surface.sphere(42), ex, ex, "
                           "lambda p: 0 * p[:, 0], n_vertices=10**9, rng=0)",
    "synthesize_geometry": "texsynth.geometry.synthesize_geometry(texsynth.data.volume('pebbles', 24), 10**5, rng=0)",
    "feature_aligned_surface": "texsynth.surface.feature_aligned_surface(texsynth.surface.sphere(42), ex, "
                               "curves=np.arange(10), n_vertices=10**9, rng=0)",
    "feature_aligned_texture": "texsynth.feature_aligned_texture(ex, np.broadcast_to(np.True_, (100000, 100000)), "
                               "rng=0)",
    "geometry_analogies": "texsynth.geometry.geometry_analogies(texsynth.data.volume('cylinder', 24), "
                          "texsynth.data.volume('grooved_cylinder', 24), np.broadcast_to(False, (4000,) * 3), "
                          "field_a=(1, 0, 0), field_b=(1, 0, 0))",
    "mesh_to_sdf": "texsynth.geometry.mesh_to_sdf(texsynth.surface.sphere(42), 10**5)",
}


@pytest.mark.parametrize("name", list(HUGE))
def test_a_size_that_cannot_fit_is_refused_before_allocating(name):
    code = textwrap.dedent(f"""
        import resource, numpy as np
        resource.setrlimit(resource.RLIMIT_AS, (4 * 2**30, 4 * 2**30))
        import texsynth, texsynth.core.flows, texsynth.optimization, texsynth.patch, texsynth.metrics
        import texsynth.core.neighborhood, texsynth.core.pyramid
        import texsynth.procedural, texsynth.surface, texsynth.geometry
        ex = texsynth.data.load("bread")[:64, :64]
        try:
            {HUGE[name]}
        except ValueError as exc:
            print("refused", exc)
        """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    out = proc.stdout.strip()
    # refused (not a MemoryError or a kill under the 4 GiB cap: nothing large was allocated first),
    # naming the parameter and the memory it would need
    assert out.startswith("refused"), (proc.returncode, out, proc.stderr[-500:])
    assert any(word in out for word in ("size", "shape", "n_vertices", "voxels", "b=")) and "GiB" in out, out


# --------------------------------------------------------------------------- junk values for every parameter
import contextlib  # noqa: E402
import inspect  # noqa: E402
import resource  # noqa: E402

import numpy as np  # noqa: E402
from hypothesis import HealthCheck, assume, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import texsynth  # noqa: E402
from texsynth import data  # noqa: E402
from texsynth.core import flows  # noqa: E402

EX = data.load("bread")[:24, :24]
GREY = data.load("metal")[:64, :64]
# small valid calls: each bad-input trial replaces one argument of one of these
CALLS = {
    "synthesize_pixels": (texsynth.synthesize_pixels, (EX, 12), dict(neighborhood=texsynth.Neighborhood(levels=1),
                                                                     rng=0)),
    "mix_textures": (texsynth.mix_textures, ([EX, EX], 12), dict(neighborhood=texsynth.Neighborhood(levels=1),
                                                                 max_iterations=1, rng=0)),
    "synthesize_solid": (texsynth.synthesize_solid, (EX, 6),
                         dict(neighborhood=texsynth.Neighborhood(neighborhood_size=3, levels=1), passes=1, rng=0)),
    "optimize_texture": (texsynth.optimize_texture, (EX, 16),
                         dict(schedule=texsynth.optimization.Schedule(neighborhood_sizes=(8,), levels=1,
                                                                      max_iterations=1), rng=0)),
    "inpaint": (texsynth.inpaint, (EX, np.eye(24, dtype=bool)), dict(neighborhood_sizes=(8,), levels=1,
                                                                    max_iterations=1, rng=0)),
    "uncrop": (texsynth.uncrop, (EX, 32), dict(neighborhood_sizes=(8,), levels=1, max_iterations=1, rng=0)),
    "make_tileable": (texsynth.make_tileable, (EX,), dict(band=4, neighborhood_sizes=(8,), levels=1,
                                                          max_iterations=1, rng=0)),
    "animate_texture": (texsynth.animate_texture, (EX, flows.translation(12, (0.0, 1.0))),
                        dict(n_frames=2, schedule=texsynth.optimization.Schedule(neighborhood_sizes=(8,), levels=1,
                                                                                 max_iterations=1),
                             animation=texsynth.optimization.Animation(max_frame_iterations=1), rng=0)),
    "interpolate_textures": (texsynth.interpolate_textures, (EX, EX[::-1], 0.5),
                             dict(schedule=texsynth.InterpolationSchedule(stages=((1, 9),), max_iterations=1),
                                  update=texsynth.InterpolationUpdate(statistics_step=False), rng=0)),
    "patchwork": (texsynth.patchwork, (EX, 24), dict(grid_spacing=8, rng=0)),
    "patchwork_video": (texsynth.patchwork_video, (np.stack([EX] * 3), 16, 3), dict(grid_spacing=8, rng=0)),
    "patchwork_transfer": (texsynth.patchwork_transfer, (EX, EX), dict(grid_spacing=8, n_candidates=4, rng=0)),
    "heeger_bergen": (texsynth.heeger_bergen, (GREY, 32), dict(scales=2, iterations=1, rng=0)),
    "portilla_simoncelli": (texsynth.portilla_simoncelli, (GREY, 32), dict(scales=2, iterations=1, rng=0)),
    "random_phase_noise": (texsynth.random_phase_noise, (EX, 32), dict(rng=0)),
    "tile_and_blend": (texsynth.tile_and_blend, (EX, 32), dict(rng=0)),
    "tile_and_blend_at": (texsynth.tile_and_blend_at, (EX, [0, 5], [3, -7]), dict(rng=0)),
    "efros_leung": (texsynth.efros_leung, (EX, 12), dict(neighborhood_size=5, rng=0)),
    "synthesize_controlled": (texsynth.synthesize_controlled, (EX, 12),
                              dict(neighborhood=texsynth.Neighborhood(levels=1), orientation=0.3, magnification=1.2,
                                   exemplar_b=EX[::-1], blend=0.5, rng=0)),
    "quilt": (texsynth.quilt, (EX, 32), dict(block=12, rng=0)),
    "quilt_transfer": (texsynth.quilt_transfer, (EX, EX), dict(block=12, iterations=1, rng=0)),
    "patch_sampling": (texsynth.patch_sampling, (EX, 32), dict(block=12, rng=0)),
    "near_regular_texture": (texsynth.near_regular_texture, (EX, 32), dict(lattice=(8, 8, 0, 0), rng=0)),
    "synthesize": (texsynth.synthesize, (EX, 32), dict(preset="quilt", rng=0)),
    "graphcut_texture": (texsynth.graphcut_texture, (EX, 32), dict(block=12, refine=1, rng=0)),
    "carve_seams": (texsynth.carve_seams, (EX, (20, 18)), dict()),
    "wang_texture": (texsynth.wang_texture, (EX, 40), dict(tile=12, rng=0)),
    "wang_tiles": (texsynth.wang_tiles, (EX, 12), dict(rng=0)),
    "wang_tiling": (texsynth.wang_tiling, (texsynth.wang_tiles(EX, 12, rng=0), 40), dict(rng=0)),
    "dynamic_texture": (texsynth.dynamic_texture, (np.stack([EX, EX[::-1], EX[:, ::-1], EX]), 6), dict(rng=0)),
    "video_texture": (texsynth.video_texture, (np.stack([EX, EX[::-1], EX[:, ::-1], EX[::-1, ::-1]] * 3), 8),
                      dict(filter_taps=2, rng=0)),
    "graphcut_video": (texsynth.graphcut_video, (np.stack([EX, EX[::-1], EX[:, ::-1], EX[::-1, ::-1]] * 2), 10),
                       dict(block=(4, 24, 24), rng=0)),
    "stylize_video": (texsynth.stylize_video, (np.stack([EX, EX[::-1], EX[:, ::-1]]), {0: EX[..., ::-1]}),
                      dict(rng=0)),
    "feature_aligned_texture": (texsynth.feature_aligned_texture, (EX, np.eye(24, dtype=bool)),
                                dict(schedule=texsynth.optimization.Schedule(levels=1, max_iterations=2), rng=0)),
    "graphcut_merge": (texsynth.graphcut_merge, (EX, EX[::-1]), dict(from_a=np.eye(24, dtype=bool),
                                                                    from_b=np.eye(24, dtype=bool)[::-1])),
}


def test_every_method_of_the_registry_gets_junk():
    from texsynth.registry import METHODS

    functions = {m.target.split(":")[1] for m in METHODS.values() if not m.target.startswith("procedural:")}
    assert functions <= set(CALLS), functions - set(CALLS)
LONG_RUNNING = {"iterations", "max_iterations", "max_frame_iterations", "passes", "mean_shift_iterations", "levels",
                "k", "alpha_steps", "statistics_bands", "max_set_size", "max_neighborhoods", "max_feature_points"}
JUNK = st.sampled_from([None, float("nan"), float("inf"), -1, 0, -0.5, 10**12, 1e308, True, "x", [1, 2],
                        (0, 0), np.zeros(3), np.full((24, 24, 3), np.nan), {}])


@contextlib.contextmanager
def _memory_limit(extra=4 * 2**30):
    """Cap this process's address space at its current size plus ``extra`` while a trial runs."""
    with open("/proc/self/status") as f:
        size = next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:"))
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (size + extra, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


@pytest.mark.filterwarnings("ignore:grid_spacing .* makes cells reach beyond")  # small inputs, on purpose
@pytest.mark.parametrize("name", list(CALLS))
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_junk_in_any_parameter_is_a_clear_error(name, data):
    func, args, kwargs = CALLS[name]
    params = [p for p in inspect.signature(func).parameters if p not in ("progress", "return_info")]
    param = data.draw(st.sampled_from(params), label="parameter")
    value = data.draw(JUNK, label="value")
    # a huge count of iterations, passes or candidates is valid: it would run, for years
    assume(not (isinstance(value, int) and value > 10**6 and param in LONG_RUNNING))
    bound = inspect.signature(func).bind_partial(*args, **kwargs).arguments
    bound[param] = value
    with _memory_limit():
        try:
            func(**bound)
        except (ValueError, TypeError) as exc:
            # the message names the parameter (or, for a value inside a container, a parameter's entry)
            assert param in str(exc) or param.rstrip("s") in str(exc), f"{param}={value!r}: {exc}"
        except FileNotFoundError as exc:  # a str given for an image is a file name (docs/conventions.md, Images)
            assert isinstance(value, str) and str(exc).startswith(f"{param}: "), f"{param}={value!r}: {exc}"


# --------------------------------------------------------------------------- the small public helpers
from texsynth import surface  # noqa: E402
from texsynth.core._validate import memory_limit  # noqa: E402
from texsynth.core import neighborhood, pyramid  # noqa: E402
from texsynth.procedural import apply_colormap  # noqa: E402

HELPERS = {
    "sphere": (surface.sphere, (42,), dict(radius=1.0)),
    "torus": (surface.torus, (50,), dict(major_radius=1.0, minor_radius=0.4)),
    "bumpy": (surface.bumpy, (42,), dict(amplitude=0.1, frequency=2.0, rng=0)),
    "default_splotch": (surface.default_splotch, ((8, 12),), dict(rng=0)),
    "scanned_mesh": (surface.scanned_mesh, ("bunny",), dict()),
    "apply_colormap": (apply_colormap, (np.linspace(0, 1, 5), [(0, 0, 0), "#ffffff"]), dict(dtype=np.float32)),
    # the shared core: every option a user passes straight through to it
    "patches_within": (neighborhood.patches_within, (np.ones((8, 8), bool), 2), dict()),
    "all_patches": (neighborhood.all_patches, (np.zeros((8, 8, 1)), 2), dict(mode="wrap")),
    "extract": (neighborhood.extract, (np.zeros((8, 8, 1)), [[0, 0]], 2), dict(mode="wrap")),
    "accumulate": (neighborhood.accumulate, (np.ones((1, 2, 2, 1)), [[0, 0]], (4, 4)),
                   dict(patch_weights=[1.0], pixel_weights=np.ones((2, 2)), mode="wrap")),
    "grid_centers": (neighborhood.grid_centers, ((8, 8), 2, 2), dict(mode="wrap")),
    "gaussian_falloff": (neighborhood.gaussian_falloff, (3,), dict(sigma=1.0)),
    "footprint": (neighborhood.footprint, (3,), dict(shape="disc")),
    "causal_parts": (neighborhood.causal_parts, (3,), dict(shape="disc")),
    "downsample": (pyramid.downsample, (np.zeros((8, 8)),), dict(spatial_dims=2, mode="wrap")),
    "upsample": (pyramid.upsample, (np.zeros((4, 4)), (8, 8)), dict(spatial_dims=2, mode="wrap")),
    "gaussian_pyramid": (pyramid.gaussian_pyramid, (np.zeros((8, 8)), 2), dict(spatial_dims=2, mode="wrap")),
    "laplacian_pyramid": (pyramid.laplacian_pyramid, (np.zeros((8, 8)), 2), dict(spatial_dims=2, mode="wrap")),
    "max_levels": (pyramid.max_levels, ((8, 8),), dict()),
    "max_scales": (pyramid.max_scales, ((8, 8),), dict()),
    "warp": (flows.warp, (np.zeros((4, 4)), np.zeros((4, 4, 2))), dict(mode="wrap")),
    "translation": (flows.translation, ((4, 4), (0.0, 1.0)), dict()),
}
HELPER_JUNK = st.sampled_from([None, float("nan"), float("inf"), -1, 0, -0.5, 10**12, 1e308, True, "x", [1, 2],
                               (0, 0), (2.5, 3), np.zeros(3), np.full((3, 3), np.nan), np.array(["a", "b"]), {},
                               object()])


@pytest.mark.parametrize("name", list(HELPERS))
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_junk_in_a_helper_is_a_clear_error(name, data):
    func, args, kwargs = HELPERS[name]
    bound = inspect.signature(func).bind_partial(*args, **kwargs).arguments
    param = data.draw(st.sampled_from(list(bound)), label="parameter")
    bound[param] = data.draw(HELPER_JUNK, label="value")
    with _memory_limit():
        try:
            func(**bound)
        except (ValueError, TypeError) as exc:
            assert param in str(exc), f"{param}={bound[param]!r}: {exc}"
        except FileNotFoundError as exc:  # a str given for an image is a file name (docs/conventions.md, Images)
            assert isinstance(bound[param], str) and str(exc).startswith(f"{param}: "), f"{param}: {exc}"


def test_a_splotch_that_cannot_fit_is_refused_before_allocating():
    with memory_limit(1e6, "a test's limit"), pytest.raises(
            ValueError, match=r"shape=\(1000, 1000\) needs about 0\.\d GiB for the splotch, more than the 0\.0 GiB "
                              r"of a test's limit; pass a smaller shape"):
        surface.default_splotch(1000)


def test_the_memory_estimate_of_the_splotch_bounds_its_peak(monkeypatch):
    import tracemalloc

    import texsynth.surface._lapped as lapped

    estimates = []
    monkeypatch.setattr(lapped, "check_memory", lambda nbytes, *args, **kwargs: estimates.append(nbytes))
    surface.default_splotch((16, 16), rng=0)  # warm up
    tracemalloc.start()
    try:
        surface.default_splotch((300, 200), rng=0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert estimates[-1] >= peak
