"""Batch synthesis on Dask: exemplars x methods x options x seeds -> an output folder.

The implementation of :func:`texsynth.batch` and of the ``texsynth batch`` command
(see ``docs/scaling.md``). The module is private (``_batch``) so that it does not
shadow the public function ``texsynth.batch``.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io as _stdio
import json
import os
import re
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from .core._extras import install_hint

__all__ = ["batch", "BatchSummary", "item_seed"]

CONNECT_TIMEOUT = 5  # seconds to reach a scheduler given as an address
_MAX_FACTOR = 64  # a size factor beyond this is a typo (a 256 px exemplar would give 16384 px outputs)
_IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".ppm", ".pgm", ".pnm", ".gif", ".webp", ".npy"}


def _distributed():
    try:
        import distributed
    except ImportError as exc:
        raise ImportError("texsynth.batch runs on dask.distributed, which is not installed: "
                          f"{install_hint('dask')}") from exc
    return distributed


def item_seed(key):
    """The seed of one item, derived from its key alone (a 64-bit int).

    ``key`` is the item's JSON key (exemplar path relative to the input folder
    or manifest, method, options, seed index). The same key gives the same
    seed on any machine, worker or order.

    >>> item_seed('["a.png", "patchwork", {}, 0]') == item_seed('["a.png", "patchwork", {}, 0]')
    True
    """
    import numpy as np

    entropy = int.from_bytes(hashlib.sha256(key.encode()).digest()[:16], "little")
    return int(np.random.SeedSequence(entropy).generate_state(1, np.uint64)[0])


@dataclass
class BatchSummary:
    """What a batch did: one dict per item (also written as ``summary.json`` and ``summary.csv``).

    Each item has ``exemplar``, ``method``, ``options``, ``seed_index``, ``seed``
    (the derived seed passed as ``rng``), ``size``, ``output``, ``status``
    (``"done"``, ``"skipped"``: its output existed, or ``"failed"``), ``error``
    and ``seconds``.
    """

    items: list = field(default_factory=list)
    seconds: float = 0.0
    dashboard_link: str | None = None

    def count(self, status):
        """How many items have this status."""
        return sum(item["status"] == status for item in self.items)

    @property
    def failed(self):
        """The items that failed."""
        return [item for item in self.items if item["status"] == "failed"]


def _parse_size(value, name="size"):
    """None (the exemplar's size), an int, ``(height, width)`` or ``"WxH"`` as a checked ``(height, width)``, or
    a factor of each exemplar's size, ``"4x"``, kept as that text (resolved per item by :func:`_item_size`)."""
    from .core._validate import as_size

    if value is None or isinstance(value, str) and value == "":
        return None
    if isinstance(value, str) and re.fullmatch(r"\s*(\d+(\.\d*)?|\.\d+)\s*[xX]\s*", value):
        factor = float(value.strip()[:-1])
        if not 0 < factor <= _MAX_FACTOR:
            raise ValueError(f"{name} {value!r} is a factor of each exemplar's size; pass one in (0, {_MAX_FACTOR}]")
        return f"{factor:g}x"
    if isinstance(value, str):
        parts = value.lower().split("x")
        if len(parts) > 2 or not all(p.strip().isdigit() for p in parts):
            raise ValueError(f"{name} must look like WIDTHxHEIGHT (e.g. 256x256), one number or a factor of "
                             f"each exemplar's size (e.g. 4x), got {value!r}")
        value = int(parts[0]) if len(parts) == 1 else (int(parts[1]), int(parts[0]))  # WxH -> (H, W)
    return as_size(value, name)


def _item_size(size, shape):
    """An item's output ``(height, width)``: its size, a factor (``"4x"``) of the exemplar's ``shape``, or the
    exemplar's own size (None); a factor's sides are rounded to the nearest pixel."""
    if size is None:
        return tuple(shape[:2])
    if isinstance(size, str):
        return tuple(max(1, int(side * float(size[:-1]) + 0.5)) for side in shape[:2])
    return tuple(size)


def _output_suffix(path):
    """The output format of an exemplar's items: float exemplars (float TIFF, EXR) keep their values' range in a
    float file of their kind, every other exemplar gives a PNG of its depth."""
    from .io import image_bits

    suffix = Path(path).suffix.lower()
    if suffix == ".exr":
        return ".exr"
    try:
        return ".tif" if suffix != ".npy" and Path(path).is_file() and image_bits(path) == 32 else ".png"
    except ValueError:  # an unreadable file fails as its item, when it is read
        return ".png"


def _check_methods(methods):
    """The method names as a list; each must be a registry method taking one exemplar image to one image."""
    from .registry import METHODS

    usable = [name for name, spec in METHODS.items() if spec.inputs == "image" and spec.output == "image"]
    hint = f"pass one or more of {', '.join(usable)}"
    if isinstance(methods, str):
        methods = [methods]
    try:
        methods = list(methods)
    except TypeError:
        raise TypeError(f"methods must be a method name or a list of them, got {methods!r}") from None
    if not methods:
        raise ValueError(f"methods is empty; {hint}")
    for name in methods:
        if name in METHODS and name not in usable:
            raise ValueError(f"methods: {name!r} does not take one exemplar image to one image; {hint}")
        if name not in usable:
            raise ValueError(f"methods: {name!r} is not a method ('texsynth list' names them); {hint}")
    return methods


def _seed_indices(seeds):
    if isinstance(seeds, str):
        seeds = json.loads(seeds)
    if isinstance(seeds, int):
        if seeds < 1:
            raise ValueError(f"seeds must be a positive count or a list of seed indices, got {seeds}")
        return list(range(seeds))
    from .core._validate import check_positive_int

    try:
        seeds = list(seeds)
    except TypeError:
        raise TypeError(f"seeds must be a positive count or a list of seed indices, got {seeds!r}") from None
    return [check_positive_int(s, "seeds", minimum=0) for s in seeds]


def _rows(inputs, methods, options, seeds, size):
    """``[(exemplar key, exemplar path, method, options, seed index, size)]`` from a folder, files or a manifest."""
    options_list = [options or {}] if isinstance(options, dict) or options is None else list(options)
    if isinstance(inputs, (list, tuple)):
        files = [(Path(p).name, Path(p)) for p in inputs]
        rows = [(k, p, m, o, None, None) for k, p in files for m in methods for o in options_list]
    else:
        path = Path(inputs)
        if path.is_dir():
            files = sorted(p for p in path.iterdir() if p.is_file() and not p.name.startswith(".")
                           and p.suffix.lower() in _IMAGE_SUFFIXES)
            rows = [(p.name, p, m, o, None, None) for p in files for m in methods for o in options_list]
        elif path.suffix.lower() in {".csv", ".json"}:
            rows = _manifest_rows(path, methods, options_list)
        elif not path.exists():
            raise FileNotFoundError(f"inputs {str(path)!r} does not exist (a folder of images or a .csv/.json manifest)")
        else:
            raise ValueError(f"inputs must be a folder of images, a list of files or a .csv/.json manifest, got {str(path)!r}")
    out = []
    for key, p, m, o, s, sz in rows:
        for index in (_seed_indices(s) if s is not None else _seed_indices(seeds)):
            out.append((key, p, m, o, index, sz if sz is not None else size))
    return out


def _manifest_rows(path, methods, options_list):
    if path.suffix.lower() == ".json":
        records = json.loads(path.read_text())
        records = records.get("items", records) if isinstance(records, dict) else records
    else:
        with open(path, newline="") as f:
            records = list(csv.DictReader(f))
    rows = []
    for number, record in enumerate(records, 1):
        if "exemplar" not in record:
            raise ValueError(f"manifest {str(path)!r}: every row needs an 'exemplar' column, got {sorted(record)}")
        exemplar = str(record["exemplar"])
        file = Path(exemplar) if Path(exemplar).is_absolute() else path.parent / exemplar
        opts = record.get("options") or None
        if isinstance(opts, str):
            opts = json.loads(opts)
        seed = record.get("seeds", record.get("seed"))
        seed = None if seed in (None, "") else (json.loads(seed) if isinstance(seed, str) else seed)
        if isinstance(seed, int) and "seed" in record and "seeds" not in record:
            seed = [seed]  # a `seed` column is one seed index, `seeds` a count or a list
        row_methods = [record["method"]] if record.get("method") else methods
        size = _parse_size(record.get("size"), f"size of manifest row {number}")
        for m in row_methods:
            for o in ([opts] if opts is not None else options_list):
                rows.append((exemplar, file, m, o, seed, size))
    return rows


def _plan(rows, folder):
    """One dict per item, with its key, derived seed and output file."""
    from .registry import METHODS

    items, names = [], {}
    for key, path, method, options, index, size in rows:
        item_key = json.dumps([key, method, options, index], sort_keys=True)
        stem = Path(key).with_suffix("").as_posix().replace("/", "_")
        tag = f"_o{hashlib.sha256(json.dumps(options, sort_keys=True).encode()).hexdigest()[:6]}" if options else ""
        name = f"{stem}_{method}{tag}_s{index}{_output_suffix(path)}"
        if name in names and names[name] != item_key:
            raise ValueError(f"two items would write {name!r}: {names[name]} and {item_key}; rename one exemplar")
        names[name] = item_key
        item = {"exemplar": str(key), "path": str(path), "method": method, "options": options, "seed_index": index,
                "seed": item_seed(item_key), "size": list(size) if isinstance(size, tuple) else size, "output": name,
                "status": "pending", "error": "", "seconds": 0.0}
        spec = METHODS.get(method)
        if spec is None:
            item.update(status="failed", error=f"unknown method {method!r}; 'texsynth list' names them")
        elif spec.inputs != "image" or spec.output != "image":
            item.update(status="failed", error=f"method {method!r} does not take one exemplar image to one image")
        elif not Path(path).is_file():
            item.update(status="failed", error=f"exemplar {str(path)!r} does not exist")
        items.append(item)
    return items


WORKER_CONFIG = {
    # Dask's nannies set MALLOC_TRIM_THRESHOLD_=65536 in their workers, so glibc hands every large numpy
    # temporary back to the system and page-faults it in again on the next allocation: 213 against 123 ms
    # for a 512^2 patchwork (benchmarks/bench_batch.py). None leaves glibc's own adaptive threshold.
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
    # the statistical profiler samples the worker's threads every 10 ms, holding the GIL: about 15 ms per item
    "distributed.worker.profile.enabled": False,
}
"""The Dask settings of the local cluster that :func:`batch` starts; use them for your own cluster too
(``dask.config.set(texsynth._batch.WORKER_CONFIG)`` before it starts)."""


def _worker_share():
    """On a Dask worker with a memory limit: the methods' pre-flight checks allow what is left of it
    (the limit minus the worker's resident memory), so an item that cannot fit is refused before it
    starts, with the figures. Elsewhere: the machine's free memory, as always."""
    from .core._validate import memory_limit

    try:
        from distributed import get_worker

        worker = get_worker()
        limit = worker.memory_manager.memory_limit
    except (ImportError, ValueError, AttributeError):
        limit = None
    if not limit:
        return contextlib.nullcontext()
    import psutil  # a dependency of distributed

    used = psutil.Process().memory_info().rss
    return memory_limit(max(0, limit - used), f"this Dask worker's memory limit ({limit / 2**30:.2f} GiB, "
                                              f"{used / 2**30:.2f} GiB in use)")


def run_item(item, folder):
    """Synthesise one item and write its output atomically; returns ``(status, error, seconds)``.

    Runs on a worker; every exception is returned as the item's error.
    """
    import inspect

    from .io import image_bits, load_image, restore_range, save_image
    from .registry import METHODS, group_options

    start = time.perf_counter()
    try:
        spec = METHODS[item["method"]]
        func = spec.function()
        # float data of any range (heights, HDR) synthesised in [0, 1], its range restored on output
        exemplar, value_range = load_image(item["path"], normalize=True)
        size = _item_size(item["size"], exemplar.shape)
        kwargs = group_options(func, dict(item["options"] or {}, rng=item["seed"]))
        args = [exemplar]
        if spec.size:
            if inspect.signature(func).parameters[spec.size].kind is inspect.Parameter.KEYWORD_ONLY:
                kwargs[spec.size] = size
            else:
                args.append(size)
        with _worker_share():
            result = spec.to_unit(func(*args, **kwargs))
        bits = image_bits(item["path"]) if not str(item["path"]).endswith(".npy") else 16
        target = Path(folder) / item["output"]
        # a float TIFF stays float, an EXR keeps the exemplar's half or float samples, a PNG its 8 or 16 bits
        bits = 32 if target.suffix == ".tif" else bits if target.suffix == ".exr" else min(bits, 16)
        save_image(target, restore_range(result, value_range), overwrite=True, bits=bits)
        return "done", "", time.perf_counter() - start
    except Exception as exc:  # noqa: BLE001 - a failing item is recorded, never stops the others
        return "failed", f"{type(exc).__name__}: {exc}", time.perf_counter() - start


def _write_summary(folder, summary):
    from .core.files import atomic_write

    fields = ["exemplar", "method", "options", "seed_index", "seed", "size", "output", "status", "error", "seconds"]
    items = [{k: item[k] for k in fields} for item in summary.items]

    def write_json(tmp):
        Path(tmp).write_text(json.dumps({"seconds": summary.seconds, "done": summary.count("done"),
                                         "skipped": summary.count("skipped"), "failed": summary.count("failed"),
                                         "items": items}, indent=1))

    def write_csv(tmp):
        buffer = _stdio.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=fields)
        writer.writeheader()
        for item in items:
            writer.writerow({**item, "options": json.dumps(item["options"]), "size": json.dumps(item["size"])})
        Path(tmp).write_text(buffer.getvalue())

    atomic_write(Path(folder) / "summary.json", write_json)
    atomic_write(Path(folder) / "summary.csv", write_csv)


def _connect(distributed, client, scheduler, n_workers, processes):
    """``(client, things to close)``."""
    if client is not None:
        return client, []
    if scheduler is not None:
        try:
            return distributed.Client(scheduler, timeout=f"{CONNECT_TIMEOUT}s"), None
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(f"cannot reach the Dask scheduler at {scheduler!r} within {CONNECT_TIMEOUT} s "
                                  f"({type(exc).__name__}); is it running, and is the address right?") from None
    n = n_workers or os.cpu_count() or 1
    import dask

    # WORKER_CONFIG: without Dask's malloc trim threshold and its statistical profiler, an item costs
    # in a worker what it costs in a plain loop (docs/scaling.md)
    with dask.config.set(WORKER_CONFIG):
        cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=processes,
                                           dashboard_address=":0")
    return distributed.Client(cluster), [cluster]


def batch(inputs, output_folder, *, methods=("patchwork",), options=None, seeds=1, size=None, client=None,
          scheduler=None, n_workers=None, processes=True, overwrite=False, progress=True):
    """Synthesise exemplars x methods x options x seeds into a folder, on ``dask.distributed``.

    Examples
    --------
    >>> import shutil, tempfile, texsynth
    >>> folder = tempfile.mkdtemp()
    >>> summary = texsynth.batch([texsynth.data.path("bread")], folder, methods=["quilt"], seeds=2, size=48,
    ...                          n_workers=1, processes=False, progress=False)
    >>> [item["output"] for item in summary.items]
    ['bread_quilt_s0.png', 'bread_quilt_s1.png']
    >>> shutil.rmtree(folder)

    Every combination is one item, synthesised on a worker of a Dask
    cluster (an in-process ``LocalCluster`` unless ``client`` or
    ``scheduler`` is given) and written as soon as it is done; a re-run
    skips the items whose output exists (``docs/scaling.md``).

    Parameters
    ----------
    inputs : str, os.PathLike or list of paths
        A folder of exemplar images, a list of image files, or a manifest:
        a ``.csv`` with the columns ``exemplar`` (a path, relative to the
        manifest's folder), ``method``, ``options`` (JSON), ``seed`` (one
        seed index) or ``seeds`` (a count or a JSON list) and ``size``
        (``WxH``), the last four optional; or a ``.json`` list of objects
        with the same keys.
    output_folder : str or os.PathLike
        Where the outputs (``STEM_METHOD[_oHASH]_sINDEX.png``) and
        ``summary.json``/``summary.csv`` are written; created if needed.
    methods : sequence of str
        Registry names (``texsynth list``) of methods taking one exemplar;
        a manifest's ``method`` column overrides them.
    options : dict or list of dict
        Keyword options passed to each method (a list: one variant each), flat as
        the command line's flags: the fields of an option group by their own names
        (``{"levels": 2, "method": "exact"}``), rebuilt into the group
        (:func:`texsynth.registry.group_options`).
    seeds : int or list of int
        A count of seed indices (0 .. N-1) or the indices; an item's seed
        is derived from its key (:func:`item_seed`), not from the index
        alone, so it is the same on 1 worker or 50, in any order.
    size : int, (int, int), str, optional
        Output ``(height, width)``, ``"WxH"``, or a factor of each
        exemplar's size, ``"4x"`` (sides rounded to the nearest pixel);
        default: a manifest row's ``size``, else the exemplar's size.
        Float exemplars of any range (heights, displacement, HDR: float
        TIFF, EXR) are synthesised in [0, 1] and their range restored in a
        float output of their kind (:func:`texsynth.io.normalize_range`);
        every other exemplar gives a PNG of its depth.
    client : distributed.Client, optional
        An existing client (left open).
    scheduler : str, optional
        Address of a running scheduler, ``"tcp://HOST:PORT"``; an
        unreachable one raises ConnectionError within ``CONNECT_TIMEOUT``
        seconds. Without ``client`` or ``scheduler`` an in-process
        ``LocalCluster`` is started and closed.
    n_workers : int, optional
        Workers of that ``LocalCluster`` (default: the machine's cores), one
        thread each.
    processes : bool
        Whether the ``LocalCluster``'s workers are processes (default: most
        methods hold the GIL in Python loops) or threads (faster to start).
    overwrite : bool
        Recompute items whose output exists. Off by default: a re-run skips
        them (resume), so a killed batch completes only the missing items.
    progress : bool or callable
        One bar over the items (and the dashboard link on stderr); a
        callable receives ``(step, total, info)``.

    Returns
    -------
    BatchSummary
        One record per item; failed items carry their error and never stop
        the others.

    Raises
    ------
    ValueError, TypeError
        Before any work (nothing written, no cluster started), as the
        ``texsynth batch`` command does: for a ``size`` (or a manifest row's)
        that is not positive ``(height, width)``, ``"WxH"`` or a factor ``"4x"``, ``methods``
        naming something other than a method from one image to one image
        (``texsynth list``), or ``seeds`` that are not a count or indices.
    """
    # checked before any work: nothing is written and no cluster started for a bad argument
    methods = _check_methods(methods)
    size = _parse_size(size)
    distributed = _distributed()
    from .core._progress import Progress

    folder = Path(output_folder)
    items = _plan(_rows(inputs, methods, options, seeds, size), folder)
    folder.mkdir(parents=True, exist_ok=True)
    for item in items:  # what a killed run left of an item's output is removed when the item is written again
        if item["status"] == "pending" and (folder / item["output"]).exists() and not overwrite:
            item["status"] = "skipped"
    start = time.perf_counter()
    summary = BatchSummary(items=items)
    todo = [item for item in items if item["status"] == "pending"]
    with Progress(progress, len(items), "batch") as bar:
        bar.advance(n=len(items) - len(todo))
        if todo:
            dask_client, closing = _connect(distributed, client, scheduler, n_workers, processes)
            owned = closing is None or bool(closing)
            try:
                summary.dashboard_link = getattr(dask_client, "dashboard_link", None)
                if progress is True and summary.dashboard_link:
                    from tqdm.auto import tqdm

                    tqdm.write(f"texsynth batch: Dask dashboard at {summary.dashboard_link}", file=sys.stderr)
                futures = {dask_client.submit(run_item, item, str(folder), key=f"texsynth-{item['seed']:x}-"
                                              f"{item['output']}", pure=False): item for item in todo}
                for future in distributed.as_completed(futures):
                    item = futures[future]
                    try:
                        status, error, seconds = future.result()
                    except Exception as exc:  # noqa: BLE001 - e.g. a worker killed by the OS
                        status, error, seconds = "failed", f"{type(exc).__name__}: {exc}", 0.0
                    item.update(status=status, error=error, seconds=seconds)
                    bar.advance({"failed": summary.count("failed")})
            finally:
                if owned:
                    dask_client.close()
                for thing in closing or []:
                    thing.close()
    summary.seconds = time.perf_counter() - start
    _write_summary(folder, summary)
    return summary
