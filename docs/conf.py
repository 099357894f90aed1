"""Sphinx configuration: numpydoc API reference, Markdown pages (MyST), examples as a gallery."""

import os

project = "texsynth"
author = "texsynth developers"
copyright = "2026, texsynth developers"
release = "0.1.0"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.extlinks",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_generated", "auto_examples/*.ipynb", "auto_examples/*.py", "auto_examples/*.zip"]
autosummary_generate = True
# the families and the core re-export their public names: document what __all__ lists
autosummary_ignore_module_all = False
templates_path = ["_templates"]
numpydoc_show_class_members = False
numpydoc_validation_checks = set()
myst_heading_anchors = 3
# numpydoc References sections list papers that the text need not cite inline
suppress_warnings = ["myst.header", "ref.citation"]
extlinks = {"doi": ("https://doi.org/%s", "doi:%s")}

# The examples gallery: every examples/plot_*.py is executed and its figures become the page's
# pictures and the index's thumbnails (the examples run at small sizes and use only texsynth.data and
# skimage.data, so the whole build takes a few minutes on 2 cores). TEXSYNTH_GALLERY=0 renders the
# scripts without running them: tests/test_docs.py sets it, to check the build for warnings within
# the test suite's time (run `python -m sphinx -b html docs /tmp/html` for the real gallery).
# Examples write their PNGs into examples/output/ (ignored by git) and never into docs/.
sphinx_gallery_conf = {
    "examples_dirs": "../examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "plot_gallery": "False" if os.environ.get("TEXSYNTH_GALLERY", "1") == "0" else "True",
    "download_all_examples": False,
    "within_subsection_order": "FileNameSortKey",
}
html_theme = "alabaster"


def _methods_table():
    """docs/_generated/methods.md: the registry's methods as a table (included by methods/index.md)."""
    from pathlib import Path

    from texsynth.registry import METHODS

    rows = ["| command | function | paper | page |", "|---|---|---|---|"]
    for name, method in METHODS.items():
        module, function = method.target.split(":")
        rows.append(f"| `texsynth {name}` | `texsynth.{module}.{function}` | {method.paper} | "
                    f"{{doc}}`/methods/{method.page}` |")
    out = Path(__file__).parent / "_generated" / "methods.md"
    out.parent.mkdir(exist_ok=True)
    text = "\n".join(rows) + "\n"
    if not out.exists() or out.read_text() != text:
        out.write_text(text)



def _top_level_aliases():
    """``{module: [names]}``: the names each public module shares with the top level of texsynth.

    Their one page is the top-level one (``texsynth.optimize_texture``, what users call); the module
    pages (``_templates/autosummary/module.rst``) link to it, so no object is documented twice.
    """
    import importlib
    import inspect
    import pkgutil

    import texsynth

    top = {name: getattr(texsynth, name) for name in texsynth.__all__
           if not name.startswith("_") and not inspect.ismodule(getattr(texsynth, name))}
    out = {}
    for info in pkgutil.walk_packages(texsynth.__path__, "texsynth."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        module = importlib.import_module(info.name)
        shared = [name for name in getattr(module, "__all__", ()) if name in top and getattr(module, name) is top[name]]
        if shared:
            out[info.name] = shared
    return out


_methods_table()
autosummary_context = {"at_top": _top_level_aliases()}
# pages an earlier build generated for these names under their module (gen_modules is not cleaned)
exclude_patterns += [f"gen_modules/{module}.{name}.rst" for module, names in autosummary_context["at_top"].items()
                     for name in names]
