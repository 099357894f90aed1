"""examples/texsynth_tour.ipynb stays valid, is committed with its outputs and runs top to bottom.

The notebook is committed executed (``jupyter nbconvert --execute --to notebook --inplace``), so that
GitHub and a reader who has not run it see its pictures. Jupyter is not a test dependency: the
notebook is read with the json module, checked against the nbformat 4 structure, and its code cells
are executed in order in one namespace with matplotlib's Agg backend, from a folder of its own (a
user's download runs anywhere: its exemplars ship in ``texsynth.data``).
"""

import json
from pathlib import Path

import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "examples" / "texsynth_tour.ipynb"


def _load():
    return json.loads(NOTEBOOK.read_text(encoding="utf-8"))


def test_notebook_is_valid_nbformat4_and_committed_with_its_outputs():
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
    counts, images = [], 0
    for cell in cells:
        assert cell["cell_type"] in {"code", "markdown", "raw"}
        assert isinstance(cell["metadata"], dict)
        assert isinstance(cell["source"], (str, list))
        if isinstance(cell["source"], list):
            assert all(isinstance(line, str) for line in cell["source"])
        source = "".join(cell["source"])
        assert "../shared" not in source and "benchmarks/photos" not in source, "use texsynth.data, not files a user lacks"
        if cell["cell_type"] == "code":
            assert not any(line.lstrip().startswith(("%", "!")) for line in source.splitlines()), (
                "IPython magics and shell escapes do not run outside Jupyter; use plain Python"
            )
            counts.append(cell["execution_count"])
            assert all(out["output_type"] != "error" for out in cell["outputs"])
            images += sum("image/png" in out.get("data", {}) for out in cell["outputs"])
        else:
            assert "outputs" not in cell and "execution_count" not in cell
    # executed once, top to bottom, and saved with its pictures (re-run it with nbconvert after editing)
    assert counts == list(range(1, len(counts) + 1)), f"execution counts {counts}: run the notebook top to bottom"
    assert images >= 2
    assert NOTEBOOK.stat().st_size < 2_000_000, "keep the figures small: the notebook is part of every checkout"


@pytest.mark.slow
def test_notebook_runs_top_to_bottom(monkeypatch, tmp_path):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)  # anywhere: the exemplars ship in texsynth.data
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
