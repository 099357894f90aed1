"""Everything a user could write with version 0.1 still works, with a warning naming the new spelling."""

import importlib
import subprocess
import sys

import pytest

import texsynth

OLD_PATHS = {  # old module path, a name imported from it, the new public spelling
    "texsynth.multisource": ("mix_textures", "texsynth.pixel.mix_textures"),
    "texsynth.patchwork": ("patchwork_video", "texsynth.patch.patchwork_video"),
    "texsynth.interpolation": ("interpolate_textures", "texsynth.optimization.interpolate_textures"),
    "texsynth.heeger_bergen": ("match_histogram", "texsynth.statistical.match_histogram"),
    "texsynth.portilla_simoncelli": ("ps_statistics", "texsynth.statistical.ps_statistics"),
    "texsynth.nearest": ("PatchIndex", "texsynth.core.search.PatchIndex"),
    "texsynth.neighborhood": ("extract", "texsynth.core.neighborhood.extract"),
    "texsynth.pyramid": ("gaussian_pyramid", "texsynth.core.pyramid.gaussian_pyramid"),
    "texsynth.flows": ("rotation", "texsynth.core.flows.rotation"),
    "texsynth.tps": ("tps_rpm", "texsynth.core.tps.tps_rpm"),
    "texsynth.procedural.noise": ("perlin", "texsynth.procedural.perlin"),
    "texsynth.procedural.patterns": ("marble", "texsynth.procedural.marble"),
    "texsynth.procedural.reaction_diffusion": ("gray_scott", "texsynth.procedural.gray_scott"),
}


@pytest.mark.parametrize("old", OLD_PATHS)
def test_old_module_paths_import_with_a_warning(old):
    name, new = OLD_PATHS[old]
    module = importlib.import_module(old)
    with pytest.warns(DeprecationWarning, match=f"{old} is deprecated; use {new.replace('.', '[.]')} instead"):
        value = getattr(module, name)
    new_module, _, new_name = new.rpartition(".")
    assert value is getattr(importlib.import_module(new_module), new_name)


def test_from_old_patchwork_module_keeps_the_function():
    """``texsynth.patchwork`` was both a module and a function; the function wins, the old import still works."""
    with pytest.warns(DeprecationWarning):
        from texsynth.patchwork import patchwork_video  # noqa: F401
    assert callable(texsynth.patchwork) and texsynth.patchwork.__name__ == "patchwork"


@pytest.mark.parametrize("name", ["expectation_maximization", "irls_weights", "IRLS_EXPONENT"])
def test_em_loop_moved_to_the_core(name):
    import texsynth.core.em as em
    import texsynth.optimization as optimization

    with pytest.warns(DeprecationWarning, match=f"use texsynth.core.em.{name}"):
        assert getattr(optimization, name) is getattr(em, name)


def test_old_paths_work_in_a_fresh_process():
    """The alias modules exist before anything else is imported (as a user's script would start)."""
    code = ("import warnings; warnings.simplefilter('error')\n"
            "try:\n    from texsynth.nearest import PatchIndex\nexcept DeprecationWarning as w:\n    print(w)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "use texsynth.core.search.PatchIndex" in out


def _renamed_functions():
    import inspect

    for family in ("pixel", "patch", "optimization", "statistical", "procedural", "core.flows", "core.neighborhood",
                   "metrics"):
        module = importlib.import_module(f"texsynth.{family}")
        for name in module.__all__:
            func = getattr(module, name)
            if inspect.isfunction(func) and getattr(func, "renamed_parameters", None):
                yield f"{family}.{name}", func


@pytest.mark.parametrize("where, func", list(_renamed_functions()), ids=lambda v: v if isinstance(v, str) else "")
def test_every_renamed_parameter_is_wired(where, func):
    import inspect

    params = inspect.signature(func).parameters
    for old, new in func.renamed_parameters.items():
        assert new in params and old not in params, (where, old, new)
        with pytest.raises(TypeError, match=f"got both {old}= \\(deprecated\\) and {new}="):
            func(**{old: 1, new: 1})


def test_an_old_name_gives_the_same_result_with_a_warning():
    from texsynth import data

    ex = data.load("bumpy")[:24, :24]
    kw = dict(neighborhood_sizes=(8,), levels=1, max_iterations=1, rng=0)
    new = texsynth.optimize_texture(ex, 24, relative_grid_spacing=0.5, **kw)
    with pytest.warns(DeprecationWarning, match=r"optimize_texture\(grid_spacing=\.\.\.\) is deprecated; use "
                                                r"relative_grid_spacing=\.\.\. instead"):
        old = texsynth.optimize_texture(ex, 24, grid_spacing=0.5, **kw)
    assert (old == new).all()
    with pytest.warns(DeprecationWarning, match=r"use periodic_exemplar='periodic\+smooth' instead"):
        texsynth.ps_statistics(data.load("metal")[:64, :64], scales=2, periodic_smooth=True)
