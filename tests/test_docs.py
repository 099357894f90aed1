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
