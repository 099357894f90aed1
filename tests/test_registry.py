"""texsynth.registry is the one list of methods: the API, the docs' methods table, the command, the gallery and
texsynth.methods() agree with it."""

import dataclasses
import importlib
import re
from pathlib import Path

import pytest

import texsynth
from texsynth import cli, demo
from texsynth.registry import METHODS, SURFACE_DEMOS

ROOT = Path(__file__).resolve().parents[1]
INDEX = (ROOT / "docs" / "methods" / "index.md").read_text()
TABLE = INDEX[INDEX.index("## The methods, by paper"):INDEX.index("## ", INDEX.index("## The methods, by paper") + 5)]
# public functions that are parts or helpers of a registered method, not methods of their own
HELPERS = {"ps_statistics", "ps_step", "interpolate_statistics", "ridge_feature_map", "edge_feature_map",
           "linear_blend", "wang_tiles", "wang_tiling", "tile_and_blend_at", "find_textons",
           "apply_coordinates", "batch", "read_mesh", "write_mesh", "render_mesh", "methods",
           "analyze_exemplar", "choose_method",  # the front door's analysis and rules (texsynth.synthesize's parts)
           "learn_dynamic_texture"}  # the model behind dynamic_texture (its command)
# methods on meshes: one command of their own (`texsynth surface MESH EXEMPLAR`, --mode vertex or lapped),
# since their input and output are meshes, not images
SURFACE = {"synthesize_surface": "vertex", "lapped_textures": "lapped", "progressive_surface": "progressive",
           "feature_aligned_surface": "feature-aligned"}
# methods whose inputs are neither images nor clips (shapes, meshes, BTF samples): a command of their own each,
# function -> (family, command, page)
OWN_COMMANDS = {"synthesize_geometry": ("geometry", "geometry", "lagae"),
                "mesh_quilting": ("geometry", "mesh-quilting", "mesh_quilting"),
                "geometry_analogies": ("geometry", "geometry-analogies", "geometry_analogies"),
                "synthesize_btf": ("pixel", "btf", "btf"), "synthesize_btf_surface": ("surface", "btf", "btf")}


@pytest.mark.parametrize("name", list(METHODS))
def test_every_method_is_public_documented_and_in_the_methods_table(name):
    method = METHODS[name]
    module, function = method.target.split(":")
    func = method.function()
    family = importlib.import_module(f"texsynth.{module}")
    assert function in family.__all__, f"{function} is not exported by texsynth.{module}"
    assert function in texsynth.__all__ or module == "procedural", f"{function} is not in texsynth.__all__"
    page = ROOT / "docs" / "methods" / f"{method.page}.md"
    assert page.exists(), f"{name}: no docs page {page.name}"
    assert function in page.read_text(), f"{page.name} does not mention {function}"
    assert re.search(r"doi:|technical report", method.paper), f"{name}: its paper needs a DOI or a source"
    rows = [r for r in TABLE.splitlines() if f"`texsynth {name}`" in r]
    assert rows, f"docs/methods/index.md's table has no row with `texsynth {name}`"
    assert function in rows[0], f"docs/methods/index.md's row of `texsynth {name}` does not name {function}"
    assert f"]({method.page}.md" in rows[0], f"docs/methods/index.md's row of `texsynth {name}` does not link {method.page}.md"
    assert callable(func)


def test_every_public_algorithm_is_registered():
    registered = {m.target.split(":")[1] for m in METHODS.values()}
    for name in texsynth.__all__:
        obj = getattr(texsynth, name)
        if dataclasses.is_dataclass(obj):  # an option group (InterpolationSchedule, ...): part of its method
            continue
        if callable(obj) and name not in HELPERS and name not in SURFACE:
            assert name in registered, f"texsynth.{name} has no entry in texsynth.registry"


@pytest.mark.parametrize("function, mode", SURFACE.items())
def test_surface_methods_have_their_command_page_and_readme_row(function, mode):
    assert callable(getattr(texsynth, function))
    commands = cli.build_parser()._subparsers._group_actions[0].choices
    assert "surface" in commands and f"{mode}" in commands["surface"].format_help()
    page = getattr(texsynth, function).__module__.rpartition("._")[2]  # its module's stem: vertex_synthesis, lapped
    assert function in (ROOT / "docs" / "methods" / f"{page}.md").read_text()
    rows = [r for r in TABLE.splitlines() if "`texsynth surface" in r and function in r]
    assert rows, f"docs/methods/index.md's table has no row for {function} with `texsynth surface`"
    assert f"]({page}.md)" in rows[0]


@pytest.mark.parametrize("function, where", OWN_COMMANDS.items())
def test_methods_of_their_own_command_have_their_page_row_and_methods_entry(function, where):
    family, command, page = where
    assert function in importlib.import_module(f"texsynth.{family}").__all__
    commands = cli.build_parser()._subparsers._group_actions[0].choices
    assert command in commands
    assert function in (ROOT / "docs" / "methods" / f"{page}.md").read_text()
    rows = [r for r in TABLE.splitlines() if f"`texsynth {command}`" in r and function in r]
    assert rows and f"]({page}.md)" in rows[0], f"docs/methods/index.md needs a row of {function}"
    assert f"texsynth.{family}.{function}" in {m.function for m in texsynth.methods()}


def test_the_command_and_the_gallery_read_the_registry():
    parser = cli.build_parser()
    commands = parser._subparsers._group_actions[0].choices
    assert set(METHODS) <= set(commands)
    assert [e.slug for e in demo.ENTRIES] == [d.slug for m in METHODS.values() for d in m.demos] + [
        d.slug for d in SURFACE_DEMOS]
    assert len({e.slug for e in demo.ENTRIES}) == len(demo.ENTRIES)


def test_the_docs_table_is_written_from_the_registry(tmp_path, monkeypatch):
    import runpy

    conf = runpy.run_path(str(ROOT / "docs" / "conf.py"))
    assert "_methods_table" in conf
    table = (ROOT / "docs" / "_generated" / "methods.md").read_text()
    for name, method in METHODS.items():
        assert f"`texsynth {name}`" in table and method.page in table


def test_flat_options_are_rebuilt_into_the_option_groups_that_hold_them():
    """A manifest's or a command line's flat options reach a function that takes option groups (issue 33)."""
    from texsynth.core.em import Schedule
    from texsynth.core.search import Search
    from texsynth.optimization import optimize_texture
    from texsynth.registry import group_options

    got = group_options(optimize_texture, {"levels": 2, "max_iterations": 3, "method": "exact", "tileable": True,
                                           "nonsense": 1})
    assert got["schedule"] == Schedule(levels=2, max_iterations=3)
    assert got["search"] == Search(method="exact")
    assert got["tileable"] is True and got["nonsense"] == 1  # not an option: passed on for the function's error
    assert "terms" not in got  # a group none of whose fields is given keeps the function's default


def test_methods_lists_every_method_once_with_its_function_command_and_paper():
    found = texsynth.methods()
    assert [m.command for m in found][:len(METHODS)] == [f"texsynth {name}" for name in METHODS]
    assert {"texsynth.synthesize_surface", "texsynth.lapped_textures"} <= {m.function for m in found}
    for entry, (name, method) in zip(found, METHODS.items()):
        module, function = method.target.split(":")
        where = "texsynth" if function in texsynth.__all__ else f"texsynth.{module}"
        assert entry.function == f"{where}.{function}"
        assert eval(entry.function, {"texsynth": texsynth}) is method.function()  # the name works as written
        assert entry.paper == method.paper and entry.summary
        # one line for a notebook: no command-line syntax, no unbalanced brackets
        assert "--" not in entry.summary and entry.summary.count("(") == entry.summary.count(")"), entry.summary
    text = str(found)
    assert len(text.splitlines()) == len(found) and "texsynth.optimize_texture" in text and "Kwatra et al." in text
    assert repr(found) == text and "<table>" in found._repr_html_()
    assert found[0] == found[0]._replace()  # named tuples: fields by name


def test_the_gallery_and_the_list_open_with_example_based_synthesis():
    first = next(iter(METHODS.values()))
    assert first.inputs != "none" and demo.ENTRIES[0].sample is not None
    kinds = [m.inputs == "none" for m in METHODS.values()]
    assert kinds == sorted(kinds), "procedural methods (no exemplar) come after every example-based one"
