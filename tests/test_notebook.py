"""examples/texsynth_tour.ipynb stays valid and runs top to bottom, as a user would run it in Jupyter.

Jupyter is not a test dependency: the notebook is read with the json module, checked against the
nbformat 4 structure, and its code cells are executed in order in one namespace with matplotlib's
Agg backend, from ``examples/`` (where a user opens it).
"""

import json
from pathlib import Path

import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "examples" / "texsynth_tour.ipynb"


def _load():
    return json.loads(NOTEBOOK.read_text(encoding="utf-8"))


def test_notebook_is_valid_nbformat4_with_outputs_stripped():
    nb = _load()
    assert nb["nbformat"] == 4 and isinstance(nb["nbformat_minor"], int)
    kernelspec = nb["metadata"]["kernelspec"]
    assert {"name", "display_name", "language"} <= kernelspec.keys() and kernelspec["language"] == "python"
    assert nb["metadata"]["language_info"]["name"] == "python"
    cells = nb["cells"]
    assert any(c["cell_type"] == "code" for c in cells) and cells[0]["cell_type"] == "markdown"
    ids = [c.get("id") for c in cells]
    if nb["nbformat_minor"] >= 5:  # cell ids are required from 4.5 on, and unique
        assert all(isinstance(i, str) and i for i in ids) and len(set(ids)) == len(ids)
    for cell in cells:
        assert cell["cell_type"] in {"code", "markdown", "raw"}
        assert isinstance(cell["metadata"], dict)
        assert isinstance(cell["source"], (str, list))
        if isinstance(cell["source"], list):
            assert all(isinstance(line, str) for line in cell["source"])
        if cell["cell_type"] == "code":
            # committed without outputs, so that it diffs cleanly
            assert cell["outputs"] == [] and cell["execution_count"] is None
            source = "".join(cell["source"])
            assert not any(line.lstrip().startswith(("%", "!")) for line in source.splitlines()), (
                "IPython magics and shell escapes do not run outside Jupyter; use plain Python"
            )
        else:
            assert "outputs" not in cell and "execution_count" not in cell


@pytest.mark.slow
def test_notebook_runs_top_to_bottom(monkeypatch):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(NOTEBOOK.parent)
    monkeypatch.setattr(plt, "show", lambda *args, **kwargs: None)  # Agg cannot show; Jupyter displays inline
    namespace = {"__name__": "__main__"}
    try:
        for number, cell in enumerate(_load()["cells"]):
            if cell["cell_type"] == "code":
                source = "".join(cell["source"])
                exec(compile(source, f"{NOTEBOOK.name} cell {number}", "exec"), namespace)
    finally:
        plt.close("all")
    # every method ran on every exemplar (its time is measured in benchmarks/, never asserted here)
    assert len(namespace["results"]) == len(namespace["methods"]) * len(namespace["exemplars"])
