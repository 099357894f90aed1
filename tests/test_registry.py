"""texsynth.registry is the one list of methods: the API, the README, the docs, the command and the gallery agree with it."""

import dataclasses
import importlib
import re
from pathlib import Path

import pytest

import texsynth
from texsynth import cli, demo
from texsynth.registry import METHODS, SURFACE_DEMOS

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
TABLE = README[README.index("## Methods"):README.index("## ", README.index("## Methods") + 5)]
# public functions that are parts or helpers of a registered method, not methods of their own
HELPERS = {"ps_statistics", "ps_step", "interpolate_statistics", "ridge_feature_map", "edge_feature_map",
           "linear_blend", "wang_tiles", "wang_tiling", "tile_and_blend_at", "find_textons",
           "apply_coordinates", "batch", "read_mesh", "write_mesh", "render_mesh"}
# methods on meshes: one command of their own (`texsynth surface MESH EXEMPLAR`, --mode vertex or lapped),
# since their input and output are meshes, not images
SURFACE = {"synthesize_surface": "vertex", "lapped_textures": "lapped"}


@pytest.mark.parametrize("name", list(METHODS))
def test_every_method_is_public_documented_and_in_the_readme(name):
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
    assert rows, f"README's methods table has no row with `texsynth {name}`"
    assert function in rows[0], f"README's row of `texsynth {name}` does not name {function}"
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
    assert function in (ROOT / "docs" / "methods" / "surfaces.md").read_text()
    rows = [r for r in TABLE.splitlines() if "`texsynth surface" in r and function in r]
    assert rows, f"README's methods table has no row for {function} with `texsynth surface`"


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
