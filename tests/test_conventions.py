"""docs/conventions.md names every public parameter, and the API keeps to its names."""

import dataclasses
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

DOC = (Path(__file__).resolve().parents[1] / "docs" / "conventions.md").read_text()


def _public_modules():
    """Every public module: ``texsynth`` and each submodule with no ``_``-prefixed part in its name."""
    import texsynth

    return ["texsynth"] + sorted(m.name for m in pkgutil.walk_packages(texsynth.__path__, "texsynth.")
                                 if not any(part.startswith("_") for part in m.name.split(".")[1:]))


# every public module, so that a new one is checked without being added here
NAMESPACES = _public_modules()


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


def _options(func):
    """``(name, default)`` of every option of ``func``: its parameters, and the fields of each option group
    (a parameter whose default is a dataclass instance, such as ``search=Search()``), whose names are
    options too (the command line's flags)."""
    try:
        params = inspect.signature(func).parameters.values()
    except (TypeError, ValueError):
        return
    for p in params:
        if p.name == "self" or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        yield p.name, p.default
        if dataclasses.is_dataclass(p.default) and not isinstance(p.default, type):
            for f in dataclasses.fields(p.default):
                yield f.name, getattr(p.default, f.name)


def _parameters():
    found = {}
    for where, func in _public_callables():
        for name, _ in _options(func):
            found.setdefault(name, where)
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
    # baselines, sample clips, example shapes, swatches and BTF samples are the same every time unless a seed is
    # asked for
    if "rng" in params and not where.startswith(("texsynth.metrics.baselines", "texsynth.metrics.texture_report",
                                                 "texsynth.testing.assert_texture_like", "texsynth.data.clip",
                                                 "texsynth.data.volume", "texsynth.data.swatch",
                                                 "texsynth.data.btf")):
        assert params["rng"].default is None, f"{where}: rng must default to None"
    if "tileable" in params:
        assert params["tileable"].default is False
    # one name, one meaning (issue 33): k counts neighbours, candidates is the candidate kind (a count is
    # n_candidates), method names a search backend; "auto" is the one spelling of "chosen by the preset"
    options = dict(_options(func))
    if "k" in options and options["k"] is not inspect.Parameter.empty:
        k = options["k"]
        assert k == "auto" or (isinstance(k, int) and not isinstance(k, bool)), f"{where}: k counts neighbours, got {k!r}"
    for name in ("candidates", "method"):
        if name in options and options[name] is not inspect.Parameter.empty:
            assert isinstance(options[name], str), f"{where}: {name} is a word (a kind, a backend), got {options[name]!r}"


# --------------------------------------------------------------------------- at most 14 options (issue 33)
MAX_OPTIONS = 14  # scikit-image's largest public function takes 14


def _crowded(callables):
    """``{where: count}`` of the callables with more than ``MAX_OPTIONS`` parameters (the data counted too; an
    option group counts once however many fields it has)."""
    crowded = {}
    for where, func in callables:
        try:
            params = inspect.signature(func).parameters.values()
        except (TypeError, ValueError):
            continue
        count = sum(1 for p in params if p.name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD))
        if count > MAX_OPTIONS:
            crowded[where] = count
    return crowded


def test_no_public_function_takes_more_than_14_options():
    """Every public function and class constructor takes at most 14 parameters; related options are grouped in
    frozen dataclasses (``schedule=Schedule(...)``), each one option."""
    crowded = _crowded(_public_callables())
    assert not crowded, f"group related options (docs/conventions.md, Option groups): {crowded}"


def test_the_bound_fails_on_a_function_with_15_options():
    import texsynth.core.em as em

    def fifteen(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o):  # noqa: E741
        return a

    def grouped(exemplar, *, terms=em.Terms(), schedule=em.Schedule()):
        return exemplar

    assert _crowded([("fifteen", fifteen), ("grouped", grouped)]) == {"fifteen": 15}


MAX_LINES = 1200  # a module longer than this holds more than one paper's worth of code: split it by subject


def test_no_source_file_is_longer_than_1200_lines():
    src = Path(__file__).resolve().parents[1] / "src" / "texsynth"
    long = {str(p.relative_to(src)): n for p in src.rglob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert not long, f"split these modules by subject (docs/architecture.md): {long}"
