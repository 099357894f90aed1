"""The layering of docs/architecture.md, enforced on the source, and the lazy public namespace."""

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "texsynth"
FAMILIES = {"pixel", "patch", "optimization", "statistical", "procedural", "surface", "video", "geometry"}
TOOLS = {"io", "data", "metrics", "testing"}
FRONT = {"__init__", "__main__", "cli", "_cli_text", "_cli_values", "_cli_shapes", "demo", "registry", "_batch", "_synthesize"}
# Ruiters et al. run one Portilla-Simoncelli step per iteration (Section 4.5): documented in
# docs/architecture.md as the one import across families; and the core's one place images enter
# (as_image) reads a file name given for an image through texsynth.io, on first use; a dynamic texture's
# larger frames go through one source-coordinate map that patch-based sampling makes of the mean frame
EXCEPTIONS = {("texsynth.optimization._ruiters", "texsynth.statistical"), ("texsynth.core._validate", "texsynth.io"),
              ("texsynth.video._doretto", "texsynth.patch")}


def _module_name(path):
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path):
    """Absolute names of the texsynth modules a file imports (relative imports resolved)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("texsynth")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            if module.startswith("texsynth"):
                found.add(module)
    return name, found


def _layer(module):
    """("core" | "tool" | "family" | "front", family name or None) of a texsynth module."""
    parts = module.split(".")
    top = parts[1] if len(parts) > 1 else "__init__"
    if top == "core":
        return "core", None
    if top in FAMILIES:
        return "family", top
    if top in TOOLS:
        return "tool", None
    if top in FRONT:
        return "front", None
    raise AssertionError(f"{module} belongs to no layer of docs/architecture.md; add it there and here")


SOURCES = sorted(SRC.rglob("*.py"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(SRC)))
def test_imports_follow_the_layers(path):
    name, imported = _imports(path)
    layer, family = _layer(name)
    for target in imported:
        if target == "texsynth":
            assert layer == "front", f"{name} imports the texsynth package itself (import what you need from its layer)"
            continue
        to_layer, to_family = _layer(target)
        if (name, target) in EXCEPTIONS:
            continue
        if layer == "core":
            assert to_layer == "core", f"the core imports no family or tool, but {name} imports {target}"
        elif layer == "tool":
            assert to_layer in ("core", "tool"), f"tool {name} imports {target} ({to_layer})"
        elif layer == "family":
            assert to_layer in ("core", "tool") or to_family == family, (
                f"family {family} imports another family: {name} -> {target} "
                "(share it through the core, or document an exception in docs/architecture.md)"
            )


def test_the_documented_exception_is_real():
    """An exception listed here that the code no longer needs should be removed from the docs too."""
    for importer, target in EXCEPTIONS:
        path = SRC.joinpath(*importer.split(".")[1:]).with_suffix(".py")
        assert target in _imports(path)[1]
    text = (SRC.parents[1] / "docs" / "architecture.md").read_text()
    assert "_ruiters.py" in text and "texsynth.statistical" in text
    assert "core/_validate.py" in text and "texsynth.io.load_image" in text


def test_import_texsynth_loads_no_family_and_no_numpy():
    code = ("import sys, texsynth; print(sorted(m for m in sys.modules if m.startswith('texsynth.') "
            "and not m.startswith('texsynth.core._')), 'numpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    # nothing but the lazy-namespace machinery of texsynth.core is imported
    assert "texsynth.pixel" not in out and "texsynth.optimization" not in out and out.strip().endswith("False"), out


def test_texture_optimization_loads_neither_ruiters_nor_the_statistical_family():
    # the optimization family's Ruiters names load on first use: texture optimization in a fresh process
    # (every command-line call) does not pay for the statistical family and scipy.signal (about 0.4 s)
    code = ("import sys, texsynth; texsynth.optimize_texture; "
            "print([m for m in ('texsynth.optimization._ruiters', 'texsynth.statistical') if m in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out
    import texsynth
    import texsynth.optimization as family

    assert family.interpolate_textures is texsynth.interpolate_textures and "linear_blend" in dir(family)


def test_public_names_resolve_to_their_family():
    import texsynth

    for name in texsynth.__all__:
        obj = getattr(texsynth, name)
        module = getattr(obj, "__module__", getattr(obj, "__name__", ""))
        assert module.startswith("texsynth") or name == "__version__", name
    assert texsynth.patchwork.__module__ == "texsynth.patch._patchwork"
    assert callable(texsynth.patchwork) and callable(texsynth.heeger_bergen) and callable(texsynth.portilla_simoncelli)


def _small_runs():
    """One small return_info run of every algorithm (the info convention of docs/conventions.md)."""
    import numpy as np

    import texsynth
    from texsynth import data
    from texsynth.core import flows

    bread, metal = data.load("bread")[:40, :40], data.load("metal")[:64, :64]
    clip = np.stack([metal[:48, t:t + 48] for t in range(4)])
    two_levels = texsynth.Neighborhood(levels=2)
    return {
        "synthesize_pixels": lambda: texsynth.synthesize_pixels(bread[:24, :24], 16, neighborhood=two_levels,
                                                                return_info=True, rng=0),
        "efros_leung": lambda: texsynth.efros_leung(bread[:24, :24], 12, neighborhood_size=5, return_info=True, rng=0),
        "synthesize_controlled": lambda: texsynth.synthesize_controlled(bread, 24, neighborhood=two_levels,
                                                                        orientation=0.3, return_info=True, rng=0),
        "optimize_texture": lambda: texsynth.optimize_texture(
            bread, 40, schedule=texsynth.optimization.Schedule(neighborhood_sizes=(8,), levels=2, max_iterations=2),
            return_info=True, rng=0),
        "inpaint": lambda: texsynth.inpaint(bread, np.eye(40, dtype=bool), neighborhood_sizes=(8,), levels=1,
                                            max_iterations=1, return_info=True, rng=0),
        "uncrop": lambda: texsynth.uncrop(bread[:32, :32], 40, neighborhood_sizes=(8,), levels=1, max_iterations=1,
                                          return_info=True, rng=0),
        "make_tileable": lambda: texsynth.make_tileable(bread[:40, :40], band=8, neighborhood_sizes=(8,), levels=1,
                                                        max_iterations=1, return_info=True, rng=0),
        "animate_texture": lambda: texsynth.animate_texture(
            bread, flows.rotation(24, 0.05), n_frames=2,
            schedule=texsynth.optimization.Schedule(neighborhood_sizes=(8,), levels=1, max_iterations=1),
            animation=texsynth.optimization.Animation(max_frame_iterations=1), return_info=True, rng=0),
        "interpolate_textures": lambda: texsynth.interpolate_textures(
            bread, bread[::-1], 0.5, schedule=texsynth.InterpolationSchedule(stages=((1, 9),), max_iterations=1),
            update=texsynth.InterpolationUpdate(statistics_step=False), return_info=True, rng=0),
        "patchwork": lambda: texsynth.patchwork(bread, 48, grid_spacing=12, return_info=True, rng=0),
        "graphcut_texture": lambda: texsynth.graphcut_texture(bread, 48, block=16, return_info=True, rng=0),
        "carve_seams": lambda: texsynth.carve_seams(bread, (30, 44), return_info=True),
        "wang_tiles": lambda: texsynth.wang_tiles(bread, 16, return_info=True, rng=0),
        "wang_tiling": lambda: texsynth.wang_tiling(texsynth.wang_tiles(bread, 16, rng=0), 50, return_info=True,
                                                    rng=0),
        "wang_texture": lambda: texsynth.wang_texture(bread, 50, tile=16, return_info=True, rng=0),
        "graphcut_merge": lambda: texsynth.graphcut_merge(bread, bread[::-1], from_a=np.eye(40, dtype=bool),
                                                          from_b=np.eye(40, dtype=bool)[::-1], return_info=True),
        "patchwork_video": lambda: texsynth.patchwork_video(clip, 32, 3, grid_spacing=16, return_info=True, rng=0),
        "patchwork_transfer": lambda: texsynth.patchwork_transfer(metal, metal[::-1], grid_spacing=8, n_candidates=4,
                                                                  return_info=True, rng=0),
        "heeger_bergen": lambda: texsynth.heeger_bergen(metal, 64, scales=2, iterations=1, return_info=True, rng=0),
        "portilla_simoncelli": lambda: texsynth.portilla_simoncelli(metal, 64, scales=2, iterations=1,
                                                                    return_info=True, rng=0),
        "random_phase_noise": lambda: texsynth.random_phase_noise(bread, 64, return_info=True, rng=0),
        "tile_and_blend": lambda: texsynth.tile_and_blend(bread, 64, return_info=True, rng=0),
        "tile_and_blend_at": lambda: texsynth.tile_and_blend_at(bread, [0, 5], [3, -7], return_info=True, rng=0),
        "graphcut_video": lambda: texsynth.graphcut_video(data.clip("waves", 8, 32), 12, return_info=True, rng=0),
        "stylize_video": lambda: texsynth.stylize_video(data.clip("waves", 3, 24), {0: data.clip("flame", 2, 24)[0]},
                                                        return_info=True, rng=0),
    }


@pytest.mark.filterwarnings("ignore:grid_spacing .* makes cells reach beyond")  # small inputs, on purpose
@pytest.mark.parametrize("name", list(_small_runs()))
def test_every_info_has_seconds_stage_seconds_and_one_energy_shape(name):
    import numpy as np

    _, info = _small_runs()[name]()
    assert type(info.seconds) is float and info.seconds > 0  # a plain float, no subclass
    assert isinstance(info.stage_seconds, dict) and info.stage_seconds
    assert all(isinstance(k, str) and v >= 0 for k, v in info.stage_seconds.items())
    assert sum(info.stage_seconds.values()) <= info.seconds * 1.01 + 1e-3 or name == "heeger_bergen"  # HB: parallel
    if hasattr(info, "energy"):
        assert isinstance(info.energy, np.ndarray) and info.energy.ndim == 1 and len(info.energy)
        if hasattr(info, "stage"):
            assert info.stage.shape == info.energy.shape and np.all(np.diff(info.stage) >= 0)


# import name -> the distribution that provides it, where the two differ
DISTRIBUTIONS = {"skimage": "scikit-image", "sklearn": "scikit-learn", "PIL": "pillow", "distributed": "dask",
                 "psutil": "dask",  # psutil comes with dask[distributed], and only the batch imports it
                 "imageio_ffmpeg": "imageio-ffmpeg"}


def _declared():
    """(runtime dependencies, every extra's) as lower-case distribution names, from pyproject.toml."""
    import tomllib

    project = tomllib.loads((SRC.parents[1] / "pyproject.toml").read_text())["project"]

    def names(specs):
        return {re.split(r"[\s\[<>=!~;]", spec, maxsplit=1)[0].lower() for spec in specs}

    return names(project["dependencies"]), names(s for extra in project["optional-dependencies"].values()
                                                 for s in extra)


def test_every_third_party_import_is_declared():
    runtime, extras = _declared()
    imported = set()
    for path in SOURCES:
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            if isinstance(node, ast.Import):
                imported |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and not node.level:
                imported.add(node.module.split(".")[0])
    third_party = {m for m in imported if m not in sys.stdlib_module_names and m != "texsynth"}
    undeclared = {m for m in third_party if DISTRIBUTIONS.get(m, m).lower() not in runtime | extras}
    assert not undeclared, f"imported but not declared in pyproject.toml: {sorted(undeclared)}"
    # texsynth.io reads and writes through imageio's Pillow plugin and writes BigTIFF with tifffile; the BTF
    # textons cluster with scikit-learn (imported on first use, so not told apart from an extra's import here)
    assert {"imageio", "pillow", "tifffile", "scikit-learn"} <= runtime


def _private_imports(path):
    """``from M import _name`` lines of one file: names private to another module (dunders aside).

    A private submodule imported by its own package (``from . import _exact`` in ``core/search``) is
    the package's business and not counted; one imported from outside its package is.
    """
    importer = _module_name(path)
    package = importer if path.name == "__init__.py" else importer.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if not isinstance(node, ast.ImportFrom) or node.module == "__future__":
            continue
        module = "." * node.level + (node.module or "")
        if node.level:
            base = package.split(".")
            absolute = ".".join(base[: len(base) - node.level + 1] + ([node.module] if node.module else []))
        else:
            absolute = node.module
        for alias in node.names:
            name = alias.name
            if not name.startswith("_") or (name.startswith("__") and name.endswith("__")):
                continue
            submodule = SRC.parent.joinpath(*absolute.split("."), name)
            is_module = submodule.with_suffix(".py").is_file() or (submodule / "__init__.py").is_file()
            if is_module and (importer == absolute or importer.startswith(absolute + ".")):
                continue
            found.append(f"{path.relative_to(SRC)}: from {module} import {name}")
    return found


def test_modules_import_only_public_names():
    """A leading underscore means "this module only": what several modules need is a public name.

    Importing a public name from a private module (``from ..core._validate import check_memory``)
    is fine: a module's privacy is its package's business (docs/architecture.md).
    """
    offenders = [line for path in SOURCES for line in _private_imports(path)]
    assert not offenders, (f"{len(offenders)} imports of another module's private names; give each a public "
                           "name where it lives (or in the core):\n" + "\n".join(offenders))


def test_geometric_neighbours_are_chosen_in_the_search_layer():
    # mesh vertices, field samples, patch centres: every k-d tree is core.search.point_tree's
    outside = [str(p.relative_to(SRC)) for p in SOURCES if "core/search" not in p.as_posix()
               and any(isinstance(n, ast.ImportFrom) and n.module == "scipy.spatial"
                       and any(a.name in ("cKDTree", "KDTree") for a in n.names)
                       for n in ast.walk(ast.parse(p.read_text())))]
    assert not outside, f"build k-d trees with texsynth.core.search.point_tree: {outside}"


def test_the_add_an_em_method_example_of_docs_architecture_runs():
    """docs/architecture.md's "Add an EM method": a method composed of core.em's public parts, run as a doctest."""
    import doctest

    page = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"
    result = doctest.testfile(str(page), module_relative=False,
                              optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    assert result.attempted >= 5 and result.failed == 0


# One stem per algorithm (issue 33, item 6): the module of an algorithm, src/texsynth/<family>/_X.py, has
# its page docs/methods/X.md, its tests tests/test_X.py (more: test_X_<topic>.py) and its benchmark
# benchmarks/bench_X.py (more: bench_X_<topic>.py), and the registry's page= of its functions is X.
# The rule does not apply to the helper modules below: each serves an algorithm (or a family) and is
# covered by that algorithm's files, the stem given here, or by tests/test_<helper>.py of its own.
HELPER_MODULES = {
    "_patchwork_video": "patchwork",              # Harrison's report, the video section: patchwork_video
    "_patchwork_transfer": "patchwork",           # Harrison's report, texture transfer: patchwork_transfer
    "_ps_statistics": "portilla_simoncelli",      # Portilla-Simoncelli's statistics and projection step
    "_ruiters_neighborhoods": "ruiters",          # Ruiters et al.'s neighbourhood sets and correspondences
    "_augment": "wei_levoy",                      # exemplar augmentation of Wei-Levoy and mixtures (test_augment.py)
    "_options": "wei_levoy",                      # the option checks Wei-Levoy, mixtures and textons share
    "_retile": "vertex_synthesis",                # Turk's retiling and mesh hierarchy (tests/test_retile.py)
    "_field": "vertex_synthesis",                 # tangent fields, also lapped textures' (tests/test_field.py)
    "_mesh": "surfaces",                          # the surface family's Mesh (tests/test_mesh.py)
    "_meshio": "surfaces",                        # mesh files (tests/test_meshio.py)
    "_shapes": "surfaces",                        # test surfaces (tests/test_shapes.py)
    "_render": "surfaces",                        # previews (tests/test_render.py)
    "_voxelize": "lagae",                         # a closed mesh as a distance volume (tests/test_lagae.py)
}
# docs/methods pages that are no algorithm's: the index, the core's search layer and seams, the surface family,
# the front door
OTHER_PAGES = {"index", "search", "seams", "surfaces", "synthesize"}
ROOT = SRC.parents[1]


def _algorithm_modules():
    """{stem: module path} of every family module that is an algorithm (not a helper)."""
    modules = {p.stem: p for family in FAMILIES for p in (SRC / family).glob("_*.py") if p.stem != "__init__"}
    unknown = set(HELPER_MODULES) - set(modules)
    assert not unknown, f"HELPER_MODULES names modules that do not exist: {sorted(unknown)}"
    return {stem[1:]: path for stem, path in modules.items() if stem not in HELPER_MODULES}


def test_every_algorithm_has_one_stem():
    from texsynth.registry import METHODS

    algorithms = _algorithm_modules()
    missing = [f"{path.relative_to(SRC)}: {needed}" for stem, path in sorted(algorithms.items())
               for needed in (f"docs/methods/{stem}.md", f"tests/test_{stem}.py", f"benchmarks/bench_{stem}.py")
               if not (ROOT / needed).is_file()]
    assert not missing, "algorithms without their page, tests or benchmark under their module's stem:\n" + \
        "\n".join(missing)
    for stem, covering in HELPER_MODULES.items():  # a helper's files: its algorithm's (or the family's) page
        assert (ROOT / "docs" / "methods" / f"{covering}.md").is_file(), (stem, covering)
    for name, method in METHODS.items():  # the registry's page is the stem of the function's module
        stem = method.function().__module__.rpartition(".")[2]
        expected = HELPER_MODULES.get(stem, stem[1:])
        assert method.page == expected, f"{name}: page={method.page!r}, its module's stem is {expected!r}"
    for function in ("synthesize_surface", "lapped_textures"):  # the surface methods: no registry entry
        import texsynth

        assert getattr(texsynth, function).__module__.rpartition("._")[2] in algorithms, function
    stale = sorted(p.stem for p in (ROOT / "docs" / "methods").glob("*.md")
                   if p.stem not in algorithms and p.stem not in OTHER_PAGES)
    assert not stale, f"docs/methods pages named after no algorithm module: {stale}"
