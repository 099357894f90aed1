"""Gigapixel outputs chunk by chunk (issue 21): lazy dask arrays equal to the in-memory results, and
their writers (Zarr, tiled BigTIFF) and command line."""

import os
import signal
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("dask")
zarr = pytest.importorskip("zarr")
tifffile = pytest.importorskip("tifffile")

from texsynth import data  # noqa: E402
from texsynth.cli import main  # noqa: E402
from texsynth.io import load_image, save_chunked, to_uint  # noqa: E402
from texsynth.patch import patchwork  # noqa: E402
from texsynth.procedural import apply_colormap, fbm, marble, perlin, turbulence, wood  # noqa: E402
from texsynth.statistical import tile_and_blend  # noqa: E402
from conftest import interrupt_writer  # noqa: E402

# Blocks of odd shapes that cut the grids anywhere: one-pixel rows and columns, blocks wider than
# the output, blocks that do not divide it.
CHUNKS = [(64, 100), (1, 300), (150, 1), (37, 1000)]


@pytest.mark.parametrize("chunks", CHUNKS)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("make", [
    lambda **kw: perlin((150, 259), frequency=30, **kw),
    lambda **kw: turbulence((150, 259), **kw),  # octaves down to 1-pixel lattice cells
    lambda **kw: turbulence((150, 259), frequency=4, period=4, offset=(0.3, 2.0), **kw),
    lambda **kw: fbm((150, 259), octaves=5, lacunarity=2.7, **kw),
    lambda **kw: marble((150, 259), **kw),
    lambda **kw: wood((150, 259), center=(0.2, 0.9), **kw),
], ids=["perlin", "turbulence", "periodic", "fbm", "marble", "wood"])
def test_procedural_blocks_equal_the_in_memory_result_bit_for_bit(make, dtype, chunks):
    whole = make(rng=3, dtype=dtype)
    lazy = make(rng=3, dtype=dtype, chunks=chunks)
    assert lazy.shape == whole.shape and lazy.dtype == whole.dtype
    assert np.array_equal(lazy.compute(), whole)


@pytest.mark.parametrize("name", ["metal", "bread"])  # grey and colour
@pytest.mark.parametrize("chunks", CHUNKS[:3])
def test_tile_and_blend_blocks_equal_the_in_memory_result(name, chunks):
    exemplar = data.load(name)[:96, :96]
    whole = tile_and_blend(exemplar, (150, 259), rng=2)
    assert np.array_equal(tile_and_blend(exemplar, (150, 259), rng=2, chunks=chunks).compute(), whole)


@pytest.mark.parametrize("options", [{}, {"tileable": True}, {"grid_spacing": 20, "sharpness": 2, "neighbors": 3}])
@pytest.mark.parametrize("chunks", CHUNKS[::2])
def test_patchwork_blocks_equal_the_in_memory_result(options, chunks):
    exemplar = data.load("bread")
    whole = patchwork(exemplar, (150, 259), rng=5, **options)
    lazy = patchwork(exemplar, (150, 259), rng=5, chunks=chunks, **options)
    assert lazy.dtype == whole.dtype
    assert np.array_equal(lazy.compute(), whole)


def test_a_lazy_output_is_checked_per_block_not_whole():
    # 2*10^5 squared pixels (320 GB in float64) are refused in memory, but blocks of 4096 are accepted:
    # nothing is allocated until a block is asked for, and any blocks give the same pixels
    with pytest.raises(ValueError, match="memory"):
        turbulence(2 * 10**5, rng=0)
    lazy = turbulence(2 * 10**5, rng=0, chunks=4096)
    assert lazy.shape == (2 * 10**5, 2 * 10**5) and lazy.numblocks == (49, 49)
    other_blocks = turbulence(2 * 10**5, rng=0, chunks=(1000, 300))
    assert np.array_equal(lazy[8190:8194, 7000:7004].compute(), other_blocks[8190:8194, 7000:7004].compute())
    with pytest.raises(ValueError, match="chunks"):  # one block that cannot fit
        tile_and_blend(data.load("bread"), 10**6, chunks=10**6)


@pytest.mark.parametrize("call, match", [
    (lambda: perlin((8, 8, 8), chunks=4), "volume"),
    (lambda: perlin(points=[[0.5, 0.5]], chunks=4), "points"),
    (lambda: marble(64, chunks=16, return_info=True), "return_info"),
    (lambda: patchwork(data.load("bread"), 64, chunks=16, return_info=True), "return_info"),
    (lambda: tile_and_blend(data.load("bread"), 64, chunks=16, return_info=True), "return_info"),
    (lambda: turbulence(64, chunks=0), "chunks"),
    (lambda: turbulence(64, chunks=(8, 8, 8)), "chunks"),
])
def test_bad_chunk_requests_are_refused_naming_the_parameter(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_zarr_and_tiff_hold_the_in_memory_result(tmp_path):
    whole = marble((200, 300), rng=1)
    lazy = marble((200, 300), rng=1, chunks=(64, 100))
    save_chunked(tmp_path / "m.zarr", lazy)
    store = zarr.open_array(str(tmp_path / "m.zarr"))
    assert store.chunks == (64, 100, 3) and store.dtype == np.uint8
    assert np.array_equal(store[:], to_uint(whole))
    save_chunked(tmp_path / "m.tif", lazy)  # 16 bits by default; tiles rounded down to multiples of 16
    with tifffile.TiffFile(tmp_path / "m.tif") as tif:
        page = tif.pages[0]
        assert tif.is_bigtiff and page.is_tiled and (page.tilelength, page.tilewidth) == (64, 96)
        assert np.array_equal(page.asarray(), to_uint(whole, 16))
    grey = turbulence((100, 90), rng=0, chunks=40) / 2
    save_chunked(tmp_path / "g.tif", grey, bits=32)
    assert np.array_equal(tifffile.imread(tmp_path / "g.tif"), (turbulence((100, 90), rng=0) / 2).astype(np.float32))


def test_save_chunked_never_half_writes_or_overwrites(tmp_path):
    lazy = apply_colormap(turbulence((120, 80), rng=0, chunks=32) / 2)
    save_chunked(tmp_path / "t.zarr", lazy)
    with pytest.raises(FileExistsError, match="overwrite"):
        save_chunked(tmp_path / "t.zarr", lazy)
    bad = turbulence((120, 80), rng=0, chunks=32)  # up to about 1.4: outside [0, 1], found block by block
    for name in ("t.zarr", "u.zarr", "u.tif"):
        with pytest.raises(ValueError, match=r"\[0, 1\]"):
            save_chunked(tmp_path / name, bad, overwrite=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.zarr"]  # the old store is kept, nothing else left
    assert np.array_equal(zarr.open_array(str(tmp_path / "t.zarr"))[:], to_uint(lazy.compute()))
    with pytest.raises(ValueError, match="zarr"):
        save_chunked(tmp_path / "t.png", lazy)


def test_command_line_writes_blocks_to_zarr_and_tiff(tmp_path):
    photo = tmp_path / "in.png"
    from texsynth.io import save_image

    save_image(photo, data.load("bread")[:128, :128])
    assert main(["patchwork", str(photo), "-o", str(tmp_path / "p.zarr"), "--size", "300x200", "--seed", "4",
                 "--chunks", "64,100"]) == 0
    stored = zarr.open_array(str(tmp_path / "p.zarr"))
    assert stored.chunks == (64, 100, 3)
    assert np.array_equal(stored[:], to_uint(patchwork(load_image(photo), (200, 300), rng=4)))
    # a .zarr output without --chunks gets blocks of DEFAULT_CHUNKS; turbulence is mapped from [0, 2] (its range)
    assert main(["turbulence", "-o", str(tmp_path / "t.zarr"), "--size", "90x70", "--seed", "1"]) == 0
    t = turbulence((70, 90), rng=1)
    assert np.array_equal(zarr.open_array(str(tmp_path / "t.zarr"))[:], to_uint(t / 2))
    assert main(["marble", "-o", str(tmp_path / "m.png"), "--size", "90x70", "--chunks", "32"]) == 2


def test_turbulence_to_zarr_computes_each_block_once(tmp_path, monkeypatch):
    # the command line maps turbulence to [0, 1] from its range [0, 2], not by its maximum, which would be a
    # whole pass over the image before the first block is written
    import texsynth.core.chunked as chunked

    computed = []
    real = chunked.chunked_image

    def counting(size, channels, dtype, chunks, render, **kwargs):
        def spy(rows, cols):
            computed.append((rows.start, cols.start))
            return render(rows, cols)

        return real(size, channels, dtype, chunks, spy, **kwargs)

    monkeypatch.setattr(chunked, "chunked_image", counting)
    options = ["--size", "90x70", "--seed", "1"]
    assert main(["turbulence", "-o", str(tmp_path / "t.zarr"), "--chunks", "32", *options]) == 0
    assert sorted(computed) == [(r, c) for r in (0, 32, 64) for c in (0, 32, 64)]  # 3 x 3 blocks, each once
    assert main(["turbulence", "-o", str(tmp_path / "t.png"), *options]) == 0
    stored = zarr.open_array(str(tmp_path / "t.zarr"))[:]
    assert np.array_equal(stored, to_uint(load_image(tmp_path / "t.png")))  # the same as in memory
    t = turbulence((70, 90), rng=1)
    assert np.array_equal(stored, to_uint(t / 2))


def _dead_pid():
    """The pid of a process that has ended (a writer killed with ``kill -9``)."""
    proc = subprocess.Popen([sys.executable, "-c", ""])
    proc.wait()
    return proc.pid


def test_the_next_zarr_write_removes_what_a_killed_writer_left(tmp_path):
    left = tmp_path / f".t.zarr-{_dead_pid()}-0123abcd"
    (left / "c" / "0").mkdir(parents=True)
    (left / "zarr.json").write_text("{}")
    live = tmp_path / f".t.zarr-{os.getpid()}-0123abcd"  # this process's: a live writer's
    live.mkdir()
    save_chunked(tmp_path / "t.zarr", turbulence((40, 30), rng=0, chunks=16) / 2)
    assert sorted(p.name for p in tmp_path.iterdir()) == [live.name, "t.zarr"]


_INTERRUPTED_ZARR = """
import signal, sys, time
import dask.array as da
import zarr.storage._local as local
from texsynth.io import save_chunked

how, target = sys.argv[1], sys.argv[2]
if how == "own-handler":
    signal.signal(signal.SIGTERM, lambda *args: sys.exit(3))
signal.signal(signal.SIGINT, signal.default_int_handler)  # Ctrl-C, even if the test runs with SIGINT ignored
real_put = local._put
puts = []


def slow_put(path, value, exclusive=False):  # on a thread of zarr's, not the main thread
    puts.append(path)
    if len(puts) == 3:  # the metadata and one block are written: the signal arrives during the second block
        print("writing", flush=True)
        time.sleep(0.5)
    return real_put(path, value, exclusive=exclusive)


local._put = slow_put
save_chunked(target, da.full((64, 64), 0.5, chunks=16))
"""


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
@pytest.mark.parametrize("how, sig", [("default", signal.SIGTERM), ("own-handler", signal.SIGTERM),
                                      ("ctrl-c", signal.SIGINT)])
def test_a_zarr_write_interrupted_mid_block_leaves_nothing(tmp_path, how, sig):
    # the interrupted write's block lands after the clean-up unless the clean-up waits for zarr's writer threads
    script = tmp_path / "zarr_write.py"
    script.write_text(_INTERRUPTED_ZARR)
    out = tmp_path / "out"
    out.mkdir()
    returncode = interrupt_writer([script, how, out / "big.zarr"], sig)
    assert returncode == {"default": -signal.SIGTERM, "own-handler": 3, "ctrl-c": -signal.SIGINT}[how]
    assert list(out.iterdir()) == []  # no store, no hidden partial store


_OTHER_KERNELS = """
import numpy as np
from texsynth.procedural import perlin, turbulence
for make in (lambda **kw: perlin((150, 259), frequency=30, **kw), lambda **kw: turbulence((150, 259), **kw)):
    whole = make(rng=3)
    for chunks in ((64, 100), (1, 300), (150, 1)):
        assert np.array_equal(make(rng=3, chunks=chunks).compute(), whole), chunks
print("same")
"""


def test_blocks_equal_the_whole_image_with_the_oldest_simd_kernels():
    # OpenBLAS's Nehalem kernel (SSE only) rounds a product's elements by its shape, and numpy's
    # X86_V2 kernels are those of a CPU without AVX: the blocks still equal the whole image
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    env = dict(os.environ, OPENBLAS_CORETYPE="Nehalem",
               NPY_DISABLE_CPU_FEATURES=" ".join(f for f in __cpu_dispatch__ if __cpu_features__.get(f)))
    done = subprocess.run([sys.executable, "-c", _OTHER_KERNELS], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and done.stdout.strip() == "same", done.stderr[-2000:]


# --------------------------------------------------------------------------- provenance and format (issue 34)
def test_zarr_and_tiff_record_attributes_and_zarr_writes_format_2(tmp_path):
    from texsynth import __version__

    lazy = turbulence((70, 90), rng=2, chunks=32) / 2
    told = {"method": "turbulence", "options": {"octaves": 5, "size": [70, 90]}, "seed": 2}
    save_chunked(tmp_path / "t3.zarr", lazy, attributes=told)
    store = zarr.open_array(str(tmp_path / "t3.zarr"))
    assert store.metadata.zarr_format == 3 and dict(store.attrs) == {**told, "texsynth_version": __version__}
    save_chunked(tmp_path / "t2.zarr", lazy, attributes=told, zarr_format=2)
    assert (tmp_path / "t2.zarr" / ".zarray").is_file() and (tmp_path / "t2.zarr" / ".zattrs").is_file()
    store2 = zarr.open_array(str(tmp_path / "t2.zarr"))
    assert store2.metadata.zarr_format == 2 and dict(store2.attrs)["method"] == "turbulence"
    assert np.array_equal(store2[:], store[:]) and np.array_equal(store[:], to_uint(lazy.compute()))
    save_chunked(tmp_path / "t.tif", lazy, attributes=told)
    with tifffile.TiffFile(tmp_path / "t.tif") as tif:
        recorded = tif.shaped_metadata[0]
    assert recorded["method"] == "turbulence" and recorded["texsynth_version"] == __version__
    assert dict(zarr.open_array(str(save_chunked(tmp_path / "plain.zarr", lazy))).attrs) == {
        "texsynth_version": __version__}


@pytest.mark.parametrize("kwargs, error, match", [
    ({"zarr_format": 4}, ValueError, "zarr_format must be 2 or 3"),
    ({"zarr_format": True}, ValueError, "zarr_format must be 2 or 3"),
    ({"attributes": {"when": object()}}, TypeError, "JSON-serialisable"),
    ({"attributes": {"x": float("nan")}}, TypeError, "JSON-serialisable"),
    ({"attributes": {1: "a"}}, TypeError, "str keys"),
    ({"attributes": ["method"]}, TypeError, "attributes must be a dict"),
])
def test_bad_attributes_and_zarr_format_are_refused_before_writing(tmp_path, kwargs, error, match):
    with pytest.raises(error, match=match):
        save_chunked(tmp_path / "t.zarr", turbulence((40, 30), rng=0, chunks=16) / 2, **kwargs)
    with pytest.raises(ValueError, match="zarr_format is for .zarr"):
        save_chunked(tmp_path / "t.tif", turbulence((40, 30), rng=0, chunks=16) / 2, zarr_format=2)
    assert not list(tmp_path.iterdir())


def test_command_line_zarr_records_how_it_was_made_in_blocks_of_1024(tmp_path, capsys):
    from texsynth import __version__
    from texsynth.cli import DEFAULT_CHUNKS
    from texsynth.io import save_image

    assert DEFAULT_CHUNKS == 1024  # a 2048 x 2048 output is four blocks, not one
    photo = save_image(tmp_path / "granite.png", data.load("bread")[:64, :64])
    assert main(["patchwork", str(photo), "-o", str(tmp_path / "p.zarr"), "--size", "1100x40", "--seed", "4",
                 "--zarr-format", "2", "--no-progress"]) == 0
    store = zarr.open_array(str(tmp_path / "p.zarr"))
    assert store.metadata.zarr_format == 2 and store.chunks == (40, 1024, 3)
    attrs = dict(store.attrs)
    assert attrs["method"] == "patchwork" and attrs["seed"] == 4 and attrs["exemplar"] == "granite.png"
    assert attrs["texsynth_version"] == __version__ and attrs["options"]["chunks"] == 1024
    assert np.array_equal(store[:], to_uint(patchwork(load_image(photo), (40, 1100), rng=4)))
    capsys.readouterr()
    assert main(["patchwork", str(photo), "-o", str(tmp_path / "p.tif"), "--chunks", "64",
                 "--zarr-format", "2"]) == 2
    assert "--zarr-format is for a .zarr output" in capsys.readouterr().err
    assert not (tmp_path / "p.tif").exists()


def test_command_line_blocks_of_a_float_height_keep_its_range(tmp_path, capsys):
    from texsynth.io import normalize_range, restore_range, save_image

    grey = data.load("bread")[:64, :64].mean(-1)
    heights = ((grey - grey.min()) / (grey.max() - grey.min()) * 3 - 1).astype(np.float32)  # metres, [-1, 2]
    source = save_image(tmp_path / "h.tif", heights, bits=32)
    unit, value_range = normalize_range(heights)
    expected = patchwork(unit, (40, 50), rng=0)
    # a float32 store (the input's depth) holds the heights themselves
    assert main(["patchwork", str(source), "-o", str(tmp_path / "f.zarr"), "--size", "50x40", "--seed", "0"]) == 0
    stored = zarr.open_array(str(tmp_path / "f.zarr"))
    assert stored.dtype == np.float32 and "value_range" not in stored.attrs
    assert np.allclose(stored[:], restore_range(expected.astype(np.float32), value_range), atol=1e-6)
    # an 8-bit store keeps the scaled values and records what 0 and 1 stand for
    capsys.readouterr()
    assert main(["patchwork", str(source), "-o", str(tmp_path / "u.zarr"), "--size", "50x40", "--seed", "0",
                 "--bits", "8"]) == 0
    assert "0 is -1, 1 is 2" in capsys.readouterr().err
    stored = zarr.open_array(str(tmp_path / "u.zarr"))
    assert stored.attrs["value_range"] == [-1.0, 2.0] and np.array_equal(stored[:], to_uint(expected))
