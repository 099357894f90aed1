"""Examples and benchmarks keep up with the API: every import they make resolves.

The examples reproduce the papers' figures and take minutes, so the suite does not run them
(the docs build renders them without executing); this check catches the cheap breakages -
a renamed function, a module shadowed by the function of the same name - in well under a
second.
"""

import ast
import importlib
import importlib.util
import re
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = sorted((ROOT / "examples").glob("*.py")) + sorted((ROOT / "benchmarks").glob("*.py"))


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_imports_resolve(script):
    tree = ast.parse(script.read_text(), filename=str(script))
    used_as_module = {n.value.id for n in ast.walk(tree) if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if not alias.name.startswith("texsynth"):
                    continue
                obj = importlib.import_module(alias.name.split(".")[0])
                for part in alias.name.split(".")[1:]:  # `import a.b as c` binds getattr(a, "b")
                    importlib.import_module(f"{obj.__name__}.{part}")
                    obj = getattr(obj, part)
                assert isinstance(obj, types.ModuleType), (
                    f"{script.name}:{node.lineno}: `import {alias.name}` binds {obj!r}, not the module; "
                    f"use `from {alias.name} import ...`"
                )
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("texsynth"):
            module = importlib.import_module(node.module)
            for alias in node.names:
                is_module = hasattr(module, "__path__") and importlib.util.find_spec(f"{node.module}.{alias.name}")
                assert hasattr(module, alias.name) or is_module, (
                    f"{script.name}:{node.lineno}: {node.module} has no {alias.name}"
                )
                if is_module and (alias.asname or alias.name) in used_as_module:
                    # a submodule shadowed by the function of the same name is not what the script expects
                    assert isinstance(getattr(module, alias.name), types.ModuleType), (
                        f"{script.name}:{node.lineno}: `from {node.module} import {alias.name}` gives the "
                        f"function, not the module {node.module}.{alias.name}; import the names you need from it"
                    )


EXAMPLES = sorted((ROOT / "examples").glob("*.py"))
# a folder beside the checkout, the benchmarks' photographs: neither is in a user's download
OUTSIDE = re.compile(r"\.\./shared|[\"'/]shared[\"'/]|parents\[2\]|benchmarks\W+photos")


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_examples_read_only_what_a_user_downloads(script):
    """Examples read texsynth.data (and skimage.data) only, and write into docs/ only when asked (--docs)."""
    text = script.read_text()
    assert not OUTSIDE.search(text), f"{script.name} reads files outside the package: {OUTSIDE.search(text)[0]!r}"
    if script.name.startswith("plot_") and '"_static"' in text:
        assert '"--docs" in sys.argv' in text, f"{script.name} writes docs/_static without --docs"
