"""Gigapixel outputs chunk by chunk (issue 21): lazy dask arrays equal to the in-memory results, and
their writers (Zarr, tiled BigTIFF) and command line."""

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

# Blocks of odd shapes that cut the grids anywhere: one-pixel rows and columns, blocks wider than
# the output, blocks that do not divide it.
CHUNKS = [(64, 100), (1, 517), (300, 1), (37, 1000)]


@pytest.mark.parametrize("chunks", CHUNKS)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("make", [
    lambda **kw: perlin((300, 517), frequency=30, **kw),
    lambda **kw: turbulence((300, 517), **kw),  # 7 octaves down to 1-pixel lattice cells
    lambda **kw: turbulence((300, 517), frequency=4, period=4, offset=(0.3, 2.0), **kw),
    lambda **kw: fbm((300, 517), octaves=5, lacunarity=2.7, **kw),
    lambda **kw: marble((300, 517), **kw),
    lambda **kw: wood((300, 517), center=(0.2, 0.9), **kw),
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
    whole = tile_and_blend(exemplar, (300, 517), rng=2)
    assert np.array_equal(tile_and_blend(exemplar, (300, 517), rng=2, chunks=chunks).compute(), whole)


@pytest.mark.parametrize("options", [{}, {"tileable": True}, {"grid_spacing": 20, "sharpness": 2, "neighbors": 3}])
@pytest.mark.parametrize("chunks", CHUNKS[::2])
def test_patchwork_blocks_equal_the_in_memory_result(options, chunks):
    exemplar = data.load("bread")
    whole = patchwork(exemplar, (300, 517), rng=5, **options)
    lazy = patchwork(exemplar, (300, 517), rng=5, chunks=chunks, **options)
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
    # a .zarr output without --chunks gets blocks of DEFAULT_CHUNKS; turbulence is scaled by its maximum
    assert main(["turbulence", "-o", str(tmp_path / "t.zarr"), "--size", "90x70", "--seed", "1"]) == 0
    t = turbulence((70, 90), rng=1)
    assert np.array_equal(zarr.open_array(str(tmp_path / "t.zarr"))[:], to_uint(t / t.max()))
    assert main(["marble", "-o", str(tmp_path / "m.png"), "--size", "90x70", "--chunks", "32"]) == 2
