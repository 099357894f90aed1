"""texsynth.batch and `texsynth batch` (issue 21, the batch half) on a 2-worker LocalCluster."""

import json
import os
import sys
import time

import numpy as np
import pytest

pytest.importorskip("distributed")

import texsynth  # noqa: E402
from texsynth import data  # noqa: E402
from texsynth._batch import item_seed  # noqa: E402
from texsynth.io import load_image, save_image  # noqa: E402

NAMES = ["bread", "metal", "water", "brick"]
METHODS = ["patchwork", "quilt"]
SIZE = 48


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    # threads, not processes: the cluster starts in milliseconds (the library's default is processes)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as c:
        yield c


@pytest.fixture()
def exemplars(tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    for name in NAMES:
        save_image(folder / f"{name}.png", data.load(name)[:64, :64])
    return folder


def _direct(path, method, seed):
    return getattr(texsynth, method)(load_image(path), (SIZE, SIZE), rng=seed)


def test_outputs_equal_the_one_process_results_and_rerun_resumes(exemplars, tmp_path, client):
    out = tmp_path / "out"
    summary = texsynth.batch(exemplars, out, methods=METHODS, size=SIZE, client=client, progress=False)
    assert summary.count("done") == 8 and not summary.failed
    for item in summary.items:
        key = json.dumps([item["exemplar"], item["method"], {}, 0], sort_keys=True)
        assert item["seed"] == item_seed(key)
        expected = tmp_path / "expected.png"
        save_image(expected, _direct(exemplars / item["exemplar"], item["method"], item["seed"]), overwrite=True)
        np.testing.assert_array_equal(load_image(out / item["output"]), load_image(expected))
    on_disk = json.loads((out / "summary.json").read_text())
    assert on_disk["done"] == 8 and (out / "summary.csv").read_text().count("\n") == 9
    # a re-run after deleting two outputs recomputes only those two
    removed = [summary.items[0]["output"], summary.items[5]["output"]]
    before = {p.name: p.stat().st_mtime_ns for p in out.glob("*.png")}
    for name in removed:
        (out / name).unlink()
    again = texsynth.batch(exemplars, out, methods=METHODS, size=SIZE, client=client, progress=False)
    assert sorted(i["output"] for i in again.items if i["status"] == "done") == sorted(removed)
    assert again.count("skipped") == 6
    assert all(p.stat().st_mtime_ns == before[p.name] for p in out.glob("*.png") if p.name not in removed)
    assert json.loads((out / "summary.json").read_text())["skipped"] == 6


def test_same_outputs_on_one_worker_in_another_order(exemplars, tmp_path, client):
    from distributed import Client, LocalCluster

    two = texsynth.batch(exemplars, tmp_path / "two", methods=["patchwork"], seeds=2, size=SIZE, client=client,
                         progress=False)
    files = sorted(exemplars.iterdir(), reverse=True)  # the same keys (file names), another order
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as one_client:
        one = texsynth.batch(files, tmp_path / "one", methods=["patchwork"], seeds=2, size=SIZE, client=one_client,
                             progress=False)
    assert one.count("done") == two.count("done") == 8
    for item in two.items:
        np.testing.assert_array_equal(load_image(tmp_path / "one" / item["output"]),
                                      load_image(tmp_path / "two" / item["output"]))


def test_a_corrupt_file_and_an_unknown_method_are_reported_and_the_rest_runs(exemplars, tmp_path, client):
    (exemplars / "corrupt.png").write_bytes(b"not an image")
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("exemplar,method,options,seed\n"
                        "in/bread.png,patchwork,\"{\"\"grid_spacing\"\": 12}\",3\n"
                        "in/corrupt.png,patchwork,,0\n"
                        "in/metal.png,no-such-method,,0\n"
                        "in/missing.png,quilt,,0\n"
                        "in/water.png,quilt,,1\n")
    summary = texsynth.batch(manifest, tmp_path / "out", size=SIZE, client=client, progress=False)
    status = {(i["exemplar"], i["method"]): (i["status"], i["error"]) for i in summary.items}
    assert status["in/bread.png", "patchwork"][0] == "done"
    assert status["in/water.png", "quilt"][0] == "done"
    assert status["in/corrupt.png", "patchwork"][0] == "failed" and "corrupt.png" in status["in/corrupt.png", "patchwork"][1]
    assert "unknown method 'no-such-method'" in status["in/metal.png", "no-such-method"][1]
    assert "does not exist" in status["in/missing.png", "quilt"][1]
    bread = next(i for i in summary.items if i["method"] == "patchwork" and i["status"] == "done")
    assert bread["options"] == {"grid_spacing": 12} and bread["seed_index"] == 3
    csv_text = (tmp_path / "out" / "summary.csv").read_text()
    assert "no-such-method" in csv_text and "failed" in csv_text
    # the same items as a JSON manifest
    rows = [{"exemplar": "in/bread.png", "method": "patchwork", "options": {"grid_spacing": 12}, "seed": 3}]
    (tmp_path / "manifest.json").write_text(json.dumps(rows))
    again = texsynth.batch(tmp_path / "manifest.json", tmp_path / "out", size=SIZE, client=client, progress=False)
    assert [i["status"] for i in again.items] == ["skipped"] and again.items[0]["seed"] == bread["seed"]


def test_an_item_beyond_the_workers_memory_limit_is_refused_before_it_starts(exemplars, tmp_path):
    from distributed import Client, LocalCluster

    # 16384^2 colour patchwork needs about 9 GiB: it would run on this machine (20+ GiB free), but
    # not within a 1.5 GiB worker; the small item beside it runs
    rows = [{"exemplar": "in/bread.png", "method": "patchwork", "size": "16384x16384", "seed": 0},
            {"exemplar": "in/bread.png", "method": "patchwork", "seed": 1}]
    (tmp_path / "manifest.json").write_text(json.dumps(rows))
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, memory_limit="1.5GiB",
                      dashboard_address=":0") as cluster, Client(cluster) as c:
        summary = texsynth.batch(tmp_path / "manifest.json", tmp_path / "out", size=SIZE, client=c, progress=False)
    big, small = summary.items
    assert small["status"] == "done"
    assert big["status"] == "failed" and "Dask worker's memory limit (1.50 GiB" in big["error"]
    assert "size=(16384, 16384) needs about" in big["error"]  # the pre-flight check: refused before it starts


def test_an_unreachable_scheduler_fails_fast_naming_the_address(exemplars, tmp_path, monkeypatch):
    import distributed

    timeouts = []
    real = distributed.Client

    def client(*args, **kwargs):  # the real client, with the timeout it was given recorded
        timeouts.append(kwargs.get("timeout"))
        return real(*args, **kwargs)

    monkeypatch.setattr(distributed, "Client", client)
    monkeypatch.setattr("texsynth._batch.CONNECT_TIMEOUT", 1)  # the default 5 s, shortened for the suite
    with pytest.raises(ConnectionError, match=r"tcp://127.0.0.1:9.* within 1 s"):
        texsynth.batch(exemplars, tmp_path / "out", scheduler="tcp://127.0.0.1:9", size=SIZE, progress=False)
    # fast by construction: the connection is bounded by a short timeout (never a wall-time assertion)
    assert timeouts == ["1s"]


def test_without_dask_the_error_names_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ImportError, match=r"python -m pip install 'dask\[distributed\]>=2023' 'zarr>=3' \(texsynth's dask extra\)"):
        texsynth.batch(tmp_path, tmp_path / "out")


def test_the_command(exemplars, tmp_path, capsys):
    from texsynth.cli import main

    out = tmp_path / "out"
    code = main(["batch", str(exemplars), "-o", str(out), "--methods", "patchwork", "--size", "40x32",
                 "--options", '{"grid_spacing": 12}', "--workers", "2", "--threads", "--no-progress"])
    assert code == 0, capsys.readouterr()
    assert "4 done" in capsys.readouterr().out
    assert load_image(next(out.glob("bread_patchwork_*.png"))).shape[:2] == (32, 40)
    assert main(["batch", str(exemplars), "-o", str(out), "--scheduler", "tcp://127.0.0.1:9", "--no-progress"]) == 2
    assert "tcp://127.0.0.1:9" in capsys.readouterr().err


def test_a_size_factor_is_of_each_exemplar_and_float_exemplars_keep_their_range(tmp_path, client, capsys):
    from texsynth.cli import main
    from texsynth.io import normalize_range, restore_range

    folder = tmp_path / "in"
    folder.mkdir()
    save_image(folder / "bread.png", data.load("bread")[:40, :50])
    heights = data.load("metal")[:32, :32] * 6.0 - 2.0  # a height map in metres, [-2, 4]
    save_image(folder / "height.tif", heights, bits=32)
    summary = texsynth.batch(folder, tmp_path / "out", methods=["quilt"], size="1.5x", client=client, progress=False)
    assert summary.count("done") == 2, summary.failed
    outputs = {item["exemplar"]: tmp_path / "out" / item["output"] for item in summary.items}
    assert load_image(outputs["bread.png"]).shape[:2] == (60, 75)  # each exemplar's own size, times 1.5
    assert outputs["height.tif"].suffix == ".tif"  # a float exemplar gives a float file ...
    got, value_range = load_image(outputs["height.tif"], normalize=True)
    item = next(i for i in summary.items if i["exemplar"] == "height.tif")
    unit, exemplar_range = normalize_range(heights)
    expected = restore_range(texsynth.quilt(unit, (48, 48), rng=item["seed"]), exemplar_range)
    # ... holding the synthesis of the normalised heights, back in metres (float32 on disk)
    np.testing.assert_allclose(restore_range(got, value_range), expected, rtol=0, atol=1e-5)
    assert main(["batch", str(folder), "-o", str(tmp_path / "cli"), "--methods", "quilt", "--size", "2x",
                 "--threads", "--workers", "1", "--no-progress"]) == 0, capsys.readouterr().err
    assert load_image(next((tmp_path / "cli").glob("bread_*.png"))).shape[:2] == (80, 100)


def test_a_killed_batch_is_finished_by_running_it_again(exemplars, tmp_path, client):
    import signal
    import subprocess

    # 40 items of about 0.1 s each in a separate process, killed (SIGKILL: no clean-up at all) once the
    # first outputs exist; the same command again computes only the items that were not finished
    rows = [{"exemplar": f"in/{name}.png", "method": "quilt", "seed": k} for name in NAMES for k in range(10)]
    manifest = tmp_path / "manifest.json"
    manifest.write_text(json.dumps(rows))
    out = tmp_path / "out"
    command = [sys.executable, "-m", "texsynth", "batch", str(manifest), "-o", str(out), "--size", "96x96",
               "--workers", "1", "--threads", "--no-progress"]
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)

    def outputs():  # the finished outputs: a hidden .NAME-XXXXXXXX.png is one being written
        return [p for p in out.glob("*.png") if not p.name.startswith(".")]

    try:
        while proc.poll() is None and len(outputs()) < 3:
            time.sleep(0.02)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    finished = {p.name: p.stat().st_mtime_ns for p in outputs()}
    assert 3 <= len(finished) < len(rows), "the batch ended before it could be killed: give it more items"
    summary = texsynth.batch(manifest, out, size=96, client=client, progress=False)
    assert summary.count("skipped") == len(finished) and summary.count("done") == len(rows) - len(finished)
    assert all((out / name).stat().st_mtime_ns == mtime for name, mtime in finished.items())
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]  # what the kill left is cleared
    for item in summary.items[:: 7]:  # every output is complete and equal to the item's own result
        expected = tmp_path / "expected.png"
        save_image(expected, texsynth.quilt(load_image(out.parent / item["exemplar"]), (96, 96), rng=item["seed"]),
                   overwrite=True)
        np.testing.assert_array_equal(load_image(out / item["output"]), load_image(expected))


@pytest.mark.parametrize("kwargs, error, message", [
    (dict(size=0), ValueError, r"size must be positive integers \(height, width\), got \(0, 0\)"),
    (dict(size="40x0"), ValueError, r"size must be positive integers \(height, width\), got \(0, 40\)"),
    (dict(size="big"), ValueError, r"size must look like WIDTHxHEIGHT \(e.g. 256x256\), one number or a factor of "
                                   r"each exemplar's size \(e.g. 4x\), got 'big'"),
    (dict(size="0x"), ValueError, r"size '0x' is a factor of each exemplar's size; pass one in \(0, 64\]"),
    (dict(size=(32.5, 40)), ValueError, r"size must be an int or 2 integers \(height, width\), got \(32.5, 40\)"),
    (dict(methods=["patchwork", "no-such-method"]), ValueError,
     r"methods: 'no-such-method' is not a method \('texsynth list' names them\); pass one or more of .*patchwork"),
    (dict(methods="perlin"), ValueError, r"methods: 'perlin' does not take one exemplar image to one image"),
    (dict(methods=[]), ValueError, "methods is empty; pass one or more of"),
    (dict(methods=None), TypeError, "methods must be a method name or a list of them, got None"),
    (dict(seeds=[0, 1.5]), TypeError, r"seeds must be an integer >= 0, got 1.5"),
])
def test_bad_size_methods_or_seeds_are_refused_before_any_work(exemplars, tmp_path, monkeypatch, kwargs, error,
                                                              message):
    import distributed

    def no_cluster(*args, **kwargs):
        raise AssertionError("a cluster was started")

    monkeypatch.setattr(distributed, "LocalCluster", no_cluster)
    with pytest.raises(error, match=message):
        texsynth.batch(exemplars, tmp_path / "out", progress=False, **kwargs)
    assert not (tmp_path / "out").exists()


def test_the_command_refuses_an_unknown_method_before_any_work(exemplars, tmp_path, capsys):
    from texsynth.cli import main

    assert main(["batch", str(exemplars), "-o", str(tmp_path / "out"), "--methods", "patchwork,nope",
                 "--no-progress"]) == 2
    assert "texsynth: error: methods: 'nope' is not a method" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_bad_size_in_a_manifest_is_refused_naming_its_row(exemplars, tmp_path):
    (tmp_path / "manifest.csv").write_text("exemplar,size\nin/bread.png,32x32\nin/metal.png,32x-1\n")
    with pytest.raises(ValueError, match=r"size of manifest row 2 must look like WIDTHxHEIGHT .* got '32x-1'"):
        texsynth.batch(tmp_path / "manifest.csv", tmp_path / "out", progress=False)
    assert not (tmp_path / "out").exists()
