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

# Examples run when the gallery is built for publication (TEXSYNTH_GALLERY=1); the
# warning-free check in the test suite only renders their code.
sphinx_gallery_conf = {
    "examples_dirs": "../examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "plot_gallery": "True" if os.environ.get("TEXSYNTH_GALLERY") else "False",
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


_methods_table()
