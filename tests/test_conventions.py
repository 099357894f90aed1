"""docs/conventions.md names every public parameter, and the API keeps to its names."""

import dataclasses
import importlib
import inspect
import re
from pathlib import Path

import pytest

DOC = (Path(__file__).resolve().parents[1] / "docs" / "conventions.md").read_text()
NAMESPACES = ["texsynth", "texsynth.pixel", "texsynth.patch", "texsynth.optimization", "texsynth.statistical",
              "texsynth.procedural", "texsynth.surface", "texsynth.core.neighborhood", "texsynth.core.pyramid", "texsynth.core.search",
              "texsynth.core.em", "texsynth.core.flows", "texsynth.core.tps", "texsynth.core.scale", "texsynth.core.seams", "texsynth.metrics", "texsynth.testing",
              "texsynth.io", "texsynth.data"]


def _public_callables():
    for namespace in NAMESPACES:
        module = importlib.import_module(namespace)
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.ismodule(obj):
                continue
            if inspect.isclass(obj):  # results (dataclasses, exceptions) hold attributes, not parameters
                if dataclasses.is_dataclass(obj) or issubclass(obj, BaseException) or "__init__" not in vars(obj):
                    continue
                obj = obj.__init__
            if callable(obj):
                yield f"{namespace}.{name}", obj


def _parameters():
    found = {}
    for where, func in _public_callables():
        try:
            params = inspect.signature(func).parameters.values()
        except (TypeError, ValueError):
            continue
        for p in params:
            if p.name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                found.setdefault(p.name, where)
    return found


def _documented():
    names = set()
    for row in re.findall(r"^\| ([^|]+) \|", DOC[DOC.index("## Parameter names"):], re.M):
        names |= set(re.findall(r"`(\w+)`", row))
    return names


def test_every_public_parameter_is_in_the_vocabulary():
    missing = {name: where for name, where in _parameters().items() if name not in _documented()}
    assert not missing, f"add these parameters to docs/conventions.md (name: first function): {missing}"


def test_the_vocabulary_lists_no_parameter_that_is_gone():
    stale = _documented() - set(_parameters())
    assert not stale, f"docs/conventions.md lists names no public function takes: {sorted(stale)}"


@pytest.mark.parametrize("where, func", list(_public_callables()), ids=lambda v: v if isinstance(v, str) else "")
def test_rules_of_the_vocabulary(where, func):
    try:
        params = inspect.signature(func).parameters
    except (TypeError, ValueError):
        return
    if "rng" in params and not where.startswith(("texsynth.metrics.baselines", "texsynth.metrics.texture_report",
                                                 "texsynth.testing.assert_texture_like")):
        assert params["rng"].default is None, f"{where}: rng must default to None"
    if "tileable" in params:
        assert params["tileable"].default is False
