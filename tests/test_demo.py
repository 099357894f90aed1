"""`texsynth demo`, the README's first command: every gallery entry runs and is written."""

import re
import subprocess
import sys

import numpy as np
import pytest

from texsynth import demo
from texsynth.io import load_image


def test_the_real_demo_command_writes_the_gallery(tmp_path):
    # the README's command, through the installed entry point's module, on the bundled samples;
    # --only keeps it to a few entries: every entry's picture is checked in-process below
    out = tmp_path / "gallery"
    only = ["marble", "quilt_brick", "heeger_bergen_metal"]
    proc = subprocess.run([sys.executable, "-m", "texsynth", "demo", "--out", str(out), "--only", ",".join(only)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    page = (out / "index.html").read_text()
    shown = set(re.findall(r'<img src="([^"]+)"', page))
    assert shown == {f"{slug}.png" for slug in only} | {"exemplar_brick.png", "exemplar_metal.png"}
    assert not [p for p in out.iterdir() if p.name.startswith(".") and p.name != demo._MARKER]  # no temporaries
    bad = subprocess.run([sys.executable, "-m", "texsynth", "demo", "--out", str(out), "--only", "marbel"],
                         capture_output=True, text=True, timeout=600)
    assert bad.returncode == 2 and "no gallery entry named 'marbel' (did you mean 'marble'?); choose among" in bad.stderr
    assert "choose among synthesize_brick, pixels_bread" in bad.stderr  # it opens with the front door


@pytest.mark.slow
@pytest.mark.parametrize("entry", demo.ENTRIES, ids=lambda e: e.slug)
def test_every_gallery_entry_is_a_real_picture(entry, tmp_path):
    # what `texsynth demo` writes for each entry: the image and the exemplar beside it, shown on the page
    index = demo.run_demo(tmp_path, entries=[entry])
    shown = set(re.findall(r'<img src="([^"]+)"', index.read_text()))
    image = load_image(tmp_path / f"{entry.slug}.png")
    assert f"{entry.slug}.png" in shown
    assert image.std() > 0.02, entry.slug  # a real picture, not a flat or empty result
    if entry.sample:
        assert f"exemplar_{entry.sample}.png" in shown


def test_select_entries_keeps_the_gallery_order_and_names_the_choices():
    assert [e.slug for e in demo.select_entries(["wood", "marble"])] == ["marble", "wood"]
    with pytest.raises(ValueError, match="choose among synthesize_brick, pixels_bread, pixels_kcoherent_brick"):
        demo.select_entries([])


def test_every_method_family_is_in_the_gallery():
    # the issues ask each method to add itself to `texsynth demo`
    slugs = " ".join(entry.slug for entry in demo.ENTRIES)
    for family in ("marble", "wood", "reaction_diffusion", "gray_scott", "pixels", "mix", "solid", "optimize",
                   "animate", "interpolate", "patchwork", "patchwork_video", "heeger_bergen", "portilla_simoncelli",
                   "surface_vertex", "surface_lapped"):
        assert family in slugs, family
    # Heeger-Bergen is shown where it works and where it fails (a structured texture)
    titles = {e.slug: e.title for e in demo.ENTRIES}
    assert any("fails" in t for s, t in titles.items() if s.startswith("heeger_bergen"))


def test_side_by_side_keeps_height_and_channels():
    a = np.zeros((5, 3, 3))
    from texsynth.registry import _side_by_side

    joined = _side_by_side([a, a, a], gap=2)
    assert joined.shape == (5, 3 * 3 + 2 * 2, 3) and joined[:, 3:5].min() == 1.0
