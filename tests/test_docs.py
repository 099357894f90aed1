"""The documentation builds with Sphinx without a single warning.

The examples gallery is rendered without running the examples (``TEXSYNTH_GALLERY=0``, see
docs/conf.py): executing them takes minutes, which the suite leaves to the publication build.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.mark.slow
def test_docs_build_without_warnings(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "-d", str(tmp_path / "doctrees"),
         str(DOCS), str(tmp_path / "html")],
        capture_output=True, text=True, timeout=600, env={**os.environ, "TEXSYNTH_GALLERY": "0"},
    )
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert (tmp_path / "html" / "index.html").exists()


def test_no_page_or_docstring_points_at_files_a_reader_lacks():
    """The developers' folders beside the checkout (../shared: papers, notes, test textures) are no
    reference for a reader: papers are cited by DOI, examples use texsynth.data. Only the benchmarks'
    page says that the benchmarks read it."""
    root = DOCS.parent
    pages = [p for p in DOCS.rglob("*.md") if p.name != "benchmarks.md" and "auto_examples" not in p.parts]
    pages += sorted(DOCS.glob("*.rst")) + sorted((root / "src" / "texsynth").rglob("*.py"))
    pages += sorted((root / "examples").glob("*.py")) + [root / "examples" / "texsynth_tour.ipynb"]
    found = [f"{p.relative_to(root)}:{n}" for p in pages
             for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
             if "../shared" in line or "shared/notes" in line or "shared/papers" in line]
    assert not found, found
