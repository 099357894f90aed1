"""The texsynth command: list, demo, errors (methods are tested with their modules' CLI tests here too)."""

import dataclasses
import re
import subprocess
import sys

import numpy as np
import pytest

from texsynth import cli, data
from texsynth.io import load_image, save_image


def run(*argv):
    return cli.main(list(argv))


def test_list_shows_every_method(capsys):
    assert run("list") == 0
    out = capsys.readouterr().out
    assert out.startswith("demo")
    for name, method in cli.METHODS.items():
        assert f"{name}" in out and method.summary in out


def test_python_dash_m_works():
    proc = subprocess.run([sys.executable, "-m", "texsynth", "list"], capture_output=True, text=True)
    assert proc.returncode == 0 and "demo" in proc.stdout


def test_unknown_method_is_a_one_line_error_with_status_2():
    proc = subprocess.run([sys.executable, "-m", "texsynth", "frobnicate"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "invalid choice" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_every_command_is_its_functions_name_with_dashes():
    for name, method in cli.METHODS.items():
        assert name == method.target.split(":")[1].replace("_", "-"), name


@pytest.mark.parametrize("typed, suggested", [("pixels", "'synthesize-pixels'"), ("seam-carve", "'carve-seams'"),
                                              ("graphcut", "'graphcut-video' or 'graphcut-texture' or 'graphcut-merge'"),
                                              ("tile-blend", "'tile-and-blend'"), ("quilts", "'quilt'")])
def test_a_mistyped_command_names_the_likeliest(typed, suggested, capsys):
    # no aliases: an old or mistyped name is argparse's "invalid choice", with the likeliest commands first
    with pytest.raises(SystemExit) as info:
        run(typed, "in.png", "-o", "out.png")
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1
    assert f"invalid choice: '{typed}'; did you mean {suggested}" in err


def test_every_method_has_help_generated_from_its_signature(capsys):
    import inspect

    for name, method in cli.METHODS.items():
        with pytest.raises(SystemExit) as info:
            run(name, "--help")
        assert info.value.code == 0
        text = capsys.readouterr().out
        params = inspect.signature(method.function()).parameters
        for pname, param in params.items():
            if pname in cli._option_names(method, params):
                assert "--" + pname.replace("_", "-") in text, (name, pname)


def test_parse_size():
    assert cli.parse_size("64x32") == (32, 64)
    assert cli.parse_size("8x4x2") == (2, 4, 8)
    for bad in ("0x5", "axb", "1x2x3x4"):
        with pytest.raises(cli.CommandError, match="--size"):
            cli.parse_size(bad)


def test_demo_writes_gallery_and_refuses_foreign_folders(tmp_path, monkeypatch):
    from texsynth import demo

    sample = demo.Entry("identity", "identity", "none", "metal", lambda ex, seed: ex[:32, :32])
    index = demo.run_demo(tmp_path / "g", entries=[sample])
    html = index.read_text()
    assert 'src="identity.png"' in html and 'src="exemplar_metal.png"' in html
    assert np.array_equal(load_image(tmp_path / "g" / "identity.png"), data.load("metal")[:32, :32])
    demo.run_demo(tmp_path / "g", entries=[sample])  # its own folder: may be rewritten
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "thesis.tex").write_text("precious")
    with pytest.raises(FileExistsError, match="did not write"):
        demo.run_demo(foreign, entries=[sample])
    assert (foreign / "thesis.tex").read_text() == "precious"


@pytest.mark.skipif(not cli.METHODS, reason="no method registered")
def test_method_errors_exit_2_without_traceback(tmp_path, capsys):
    name, method = next((n, m) for n, m in cli.METHODS.items() if m.inputs == "image")
    assert run(name, str(tmp_path / "missing.png"), "-o", str(tmp_path / "o.png")) == 2
    err = capsys.readouterr().err
    assert err.startswith("texsynth: error:") and err.count("\n") == 1
    src = save_image(tmp_path / "in.png", data.load("bumpy"))
    assert run(name, str(src), "-o", str(src), "--overwrite") == 2
    assert "also an input" in capsys.readouterr().err
    existing = save_image(tmp_path / "exists.png", np.zeros((4, 4)))
    assert run(name, str(src), "-o", str(existing)) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert load_image(existing).max() == 0.0
    assert run(name, str(src), "-o", str(tmp_path / "o.png"), "--size", "0x3") == 2


def test_flow_and_ramp_values(tmp_path):
    flow = cli.parse_flow("sink:1.5", (8, 10))
    assert flow.shape == (8, 10, 2) and np.abs(flow).max() > 0
    with pytest.raises(cli.CommandError, match="KIND:AMOUNT"):
        cli.parse_flow("swirl:1", (8, 10))
    ramp = cli.ramp((3, 5))
    assert ramp.shape == (3, 5) and ramp[0, 0] == 0.0 and ramp[-1, -1] == 1.0


def test_procedural_command_writes_an_image_and_a_volume(tmp_path):
    assert run("marble", "-o", str(tmp_path / "m.png"), "--size", "40x24", "--seed", "1") == 0
    assert load_image(tmp_path / "m.png").shape == (24, 40, 3)
    assert run("perlin", "-o", str(tmp_path / "v.npy"), "--size", "8x6x4", "--seed", "1") == 0
    volume = np.load(tmp_path / "v.npy")
    assert volume.shape == (4, 6, 8) and 0 <= volume.min() and volume.max() <= 1  # [-1, 1] noise mapped to [0, 1]
    assert (tmp_path / "v_slice_z.png").exists()


def test_parse_weights_ramp_and_files(tmp_path):
    for n in (2, 3):
        weights = cli.parse_weights("ramp", n, (4, 9))
        # a partition of unity: the first input alone at the left edge, the last alone at the right
        np.testing.assert_allclose(sum(weights), 1.0)
        assert weights[0][0, 0] == 1.0 and weights[-1][0, -1] == 1.0
    assert cli.parse_weights("equal", 2, (4, 9)) is None
    m = save_image(tmp_path / "m.png", np.tile(np.linspace(0, 1, 9), (4, 1)))
    first, second = cli.parse_weights(str(m), 2, (4, 9))
    np.testing.assert_allclose(first + second, 1.0)
    assert second[0, -1] == 1.0 and first[0, 0] == 1.0
    with pytest.raises(cli.CommandError, match="--weights"):
        cli.parse_weights(str(m), 3, (4, 9))


def test_mix_ramp_goes_from_the_first_input_to_the_second(tmp_path):
    from texsynth.metrics import texture_energy

    a, b = data.load("bread")[:40, :40], data.load("brick")[:40, :40]
    pa, pb = save_image(tmp_path / "a.png", a), save_image(tmp_path / "b.png", b)
    out = tmp_path / "mix.png"
    assert run("mix-textures", str(pa), str(pb), "-o", str(out), "--size", "96x32", "--weights", "ramp",
               "--seed", "0") == 0
    mix = load_image(out)
    assert mix.shape == (32, 96, 3)
    left, right = mix[:, :24], mix[:, -24:]
    # each end is made of its own source: nearer (in patch energy) to it than to the other source
    assert texture_energy(left, a) < texture_energy(left, b)
    assert texture_energy(right, b) < texture_energy(right, a)


def test_pixels_and_solid_commands(tmp_path):
    src = save_image(tmp_path / "wood.png", data.load("wood")[:24, :24])
    assert run("synthesize-pixels", str(src), "-o", str(tmp_path / "p.png"), "--size", "40x32", "--seed", "0") == 0
    assert load_image(tmp_path / "p.png").shape == (32, 40, 3)
    assert run("synthesize-solid", str(src), "-o", str(tmp_path / "s.png"), "--size", "20", "--seed", "0") == 0
    volume = np.load(tmp_path / "s.npy")
    assert volume.shape == (20, 20, 20, 3)  # one number: a cube
    for axis in "zyx":
        assert load_image(tmp_path / f"s_slice_{axis}.png").shape == (20, 20, 3)


# --------------------------------------------------------------------------- grey maps, help text
def test_read_grey_map_means_the_same_in_every_layout(tmp_path):
    # one reader for --weights, --mask, --alpha-map, --features: grey, grey + alpha, RGB and
    # RGBA files (8 or 16 bit) of the same grey values give the same map; alpha is ignored
    grey = np.tile(np.linspace(0, 1, 6), (4, 1))
    alpha = np.full_like(grey, 0.25)
    files = {
        "grey": save_image(tmp_path / "g.png", grey),
        "grey16": save_image(tmp_path / "g16.png", grey, bits=16),
        "la": save_image(tmp_path / "la.png", np.stack([grey, alpha], -1)),
        "rgb": save_image(tmp_path / "rgb.png", np.stack([grey] * 3, -1)),
        "rgba": save_image(tmp_path / "rgba.png", np.stack([grey] * 3 + [alpha], -1)),
    }
    for kind, path in files.items():
        m = cli.read_grey_map(path, "--mask")
        assert m.shape == (4, 6), kind
        np.testing.assert_allclose(m, grey, atol=1 / 255, err_msg=kind)
    # --weights uses it too: a grey + alpha weight file is its grey channel, not grey and alpha averaged
    first, second = cli.parse_weights(str(files["la"]), 2, (4, 6))
    np.testing.assert_allclose(second, grey, atol=1 / 255)


def test_grouped_parameters_are_described_once(capsys):
    # animate_texture documents several parameters (now option groups) in one numpydoc entry ("As in
    # optimize_texture, for frame 1 (... a kd-tree re-ranking 4 candidates ...)"); the help used to
    # repeat that sentence under each of them. Now the first shown carries it, the others point to it.
    with pytest.raises(SystemExit):
        run("animate-texture", "--help-full")  # --help shows first sentences; --help-full the whole text
    text = capsys.readouterr().out
    assert text.count("re-ranking 4 candidates") == 1
    assert ":func:" not in text and "``" not in text  # numpydoc markup is stripped
    # and generally: no method shows the same description under two options, and every pointer
    # ("See --x.", "(see --x)") names another option of the same command that has a description
    import inspect

    for name, method in cli.METHODS.items():
        func = method.function()
        params = inspect.signature(func).parameters
        shown = cli._option_names(method, params)
        described = cli.doc_params(func, shown)
        descriptions = [d for n, d in described.items() if n in shown and len(d) > 30]
        assert len(descriptions) == len(set(descriptions)), name
        for option in shown:
            pointers = re.findall(r"[Ss]ee (--[\w-]+)", described.get(option, ""))
            assert len(pointers) <= 1, (name, option, described[option])
            for pointer in pointers:
                target = pointer[2:].replace("-", "_")
                assert target in shown and target != option, (name, option, pointer)
                assert not described[target].startswith("See --"), (name, option, pointer)


# toy functions whose docstrings borrow grouped entries through two functions, as make_tileable ->
# inpaint -> optimize_texture do
def _toy_base(image, *, size_a=1, size_b=2, iterations=3):
    """Toy base.

    Parameters
    ----------
    image : array_like
        The input.
    size_a, size_b : int
        Sizes described once for both names, in the base's own words.
    iterations : int
        Iterations, described by the base on their own.
    """


def _toy_middle(image, *, size_a=1, size_b=2, iterations=3):
    """Toy middle.

    Parameters
    ----------
    image : array_like
        The input.
    size_a, size_b, iterations
        As in :func:`_toy_base`.
    """


def _toy_top(image, *, band=1, size_a=1, size_b=2, iterations=3):
    """Toy top.

    Parameters
    ----------
    image : array_like
        The input.
    band : int
        The band.
    size_a, size_b, iterations
        As in :func:`_toy_middle`.
    """


def _toy_frames(image, *, size_a=1, size_b=2, iterations=3):
    """Toy frames.

    Parameters
    ----------
    image : array_like
        The input.
    size_a, size_b, iterations
        As in :func:`_toy_base`, for the first frame only.
    """


def test_borrowed_grouped_entries_point_at_the_flag_that_carries_them():
    # make-tileable's --levels said "See --neighborhood-sizes. (see --neighborhood-sizes)" and its
    # --max-iterations "As in optimize_texture(). (see --neighborhood-sizes)": pointers of inpaint's
    # help carried into another command. Now each name gets its own complete description, once.
    sizes = "Sizes described once for both names, in the base's own words."
    iterations = "Iterations, described by the base on their own."
    shown = ["band", "size_a", "size_b", "iterations"]
    for func in (_toy_middle, _toy_top):
        assert cli.doc_params(func, shown)["size_a"] == sizes, func
        assert cli.doc_params(func, shown)["size_b"] == "See --size-a.", func
        assert cli.doc_params(func, shown)["iterations"] == iterations, func
    # with its own words (not only "As in ..."), the entry's text is shown once, on the first option
    frames = cli.doc_params(_toy_frames, shown)
    assert frames["size_a"] == f"{sizes} As in :func:`_toy_base`, for the first frame only."
    assert frames["size_b"] == "See --size-a."
    assert frames["iterations"] == f"{iterations} (see --size-a)"
    # the pointer goes to the first option that is shown
    assert cli.doc_params(_toy_top, ["size_b", "iterations"])["size_b"] == sizes


def test_make_tileable_help_points_once_at_a_shown_flag(capsys):
    with pytest.raises(SystemExit):
        run("make-tileable", "--help")
    text = " ".join(capsys.readouterr().out.split())
    assert "(see --neighborhood-sizes)" not in text and "See --max-iterations" not in text
    assert text.count("See --neighborhood-sizes.") <= 1 and "As in inpaint()" not in text
    assert "EM iterations per (level, size) stage" in text  # --max-iterations' own description


# --------------------------------------------------------------------------- option groups
@dataclasses.dataclass(frozen=True)
class Toy:
    """A toy option group.

    Parameters
    ----------
    strength : float
        How strong the toy is, > 0.
    mask : array_like, optional
        A grey map of where the toy acts.
    guide : array_like, optional
        An image the toy follows.
    first, second : int
        Two counts with one description, long enough to be a sentence.
    mode : str
        A word of a closed vocabulary.
    loud : bool
        Whether the toy is loud.
    blend : float or array_like
        How much of the toy, a number or a map over the output.
    orientation : float or array_like, optional
        The toy's angle field.

    Examples
    --------
    >>> Toy(strength=2.0).strength
    2.0
    """

    strength: float = 1.0
    mask: object = None
    guide: object = None
    first: int = 1
    second: int = 2
    mode: str = "plain"
    loud: bool = False
    blend: object = 0.5
    orientation: object = None

    def __post_init__(self):
        if not self.strength > 0:
            raise ValueError(f"strength must be > 0, got {self.strength!r}")


@dataclasses.dataclass(frozen=True)
class OtherToy:
    """Another toy group.

    Parameters
    ----------
    first : int
        A count.
    """

    first: int = 0


def toy_synthesis(exemplar, size, *, toy=Toy(first=3), level=2, rng=None):
    """A toy synthesis with one option group.

    Parameters
    ----------
    exemplar : array_like
        The input.
    size : tuple of int
        The output's size.
    toy : Toy
        The toy's options (:class:`Toy`).
    level : int
        A plain option beside the group.
    rng : None or int
        The seed.
    """
    return np.zeros(tuple(size) + np.shape(exemplar)[2:])


@dataclasses.dataclass(frozen=True)
class _ToyMethod(cli.Method):
    """A registry entry whose function is given, not imported."""

    func: object = None

    def function(self):
        return self.func


@pytest.fixture
def toy(monkeypatch):
    """``texsynth toy``: the only method, toy_synthesis, its calls recorded as they came."""
    import functools

    calls = []

    @functools.wraps(toy_synthesis)
    def recorded(*args, **kwargs):
        calls.append(kwargs)
        return toy_synthesis(*args, **kwargs)

    method = _ToyMethod(target="toy:toy_synthesis", summary="a toy", maps=("mask", "blend"), files=("guide",),
                        ramps=("blend",), spatial="blend", fields=("orientation",), func=recorded)
    monkeypatch.setattr(cli, "METHODS", {"toy": method})
    return calls


def test_option_group_fields_are_flags_with_their_help_and_defaults(toy, capsys):
    import inspect

    with pytest.raises(SystemExit) as info:
        run("toy", "--help")
    assert info.value.code == 0
    text = capsys.readouterr().out
    flat = " ".join(text.split())
    assert "toy=Toy(...):" in text and "The toy's options (Toy)." in flat  # the group's heading and its doc
    assert "--toy " not in text and "--toy\n" not in text  # the group itself is no flag
    for flag in ("--strength STRENGTH", "--mask PATH", "--guide PATH", "--first FIRST", "--second SECOND",
                 "--mode MODE", "--loud, --no-loud", "--level LEVEL"):
        assert flag in text, flag
    assert "How strong the toy is, > 0. (default: 1.0)" in flat
    assert "Two counts with one description, long enough to be a sentence. (default: 3)" in flat  # the instance's
    assert "See --first. (default: 2)" in flat  # a grouped entry of the class: described once
    assert "grey image file" in flat and "image file. An image the toy follows." in flat
    params = inspect.signature(toy_synthesis).parameters
    assert cli._option_names(cli.METHODS["toy"], params) == ["strength", "mask", "guide", "first", "second", "mode",
                                                             "loud", "blend", "orientation", "level"]
    assert "--blend-map PATH" in text and "--transition" in text and "--orientation VALUE|PATH" in text


def test_option_group_defaults_flow_through_and_given_flags_reach_the_group(toy, tmp_path):
    ex = str(save_image(tmp_path / "ex.png", data.load("bumpy")[:8, :8]))
    assert run("toy", ex, "-o", str(tmp_path / "a.png"), "--size", "6x4") == 0
    assert "toy" not in toy[-1] and "level" not in toy[-1]  # nothing given: the function's own defaults
    assert run("toy", ex, "-o", str(tmp_path / "b.png"), "--size", "6x4", "--strength", "2.5", "--second", "7",
               "--mode", "none", "--loud", "--level", "5") == 0
    assert toy[-1]["toy"] == Toy(strength=2.5, first=3, second=7, mode="none", loud=True)  # first: the default's 3
    assert toy[-1]["level"] == 5
    assert load_image(tmp_path / "b.png").shape == (4, 6, 3)


def test_option_group_map_and_file_fields_are_read_as_images(toy, tmp_path):
    ex = str(save_image(tmp_path / "ex.png", data.load("bumpy")[:8, :8]))
    grey = np.tile(np.linspace(0, 1, 6), (4, 1))
    rgba = save_image(tmp_path / "m.png", np.stack([grey] * 3 + [np.full_like(grey, 0.5)], -1))
    guide = data.load("brick")[:4, :6]
    pg = save_image(tmp_path / "g.png", guide)
    assert run("toy", ex, "-o", str(tmp_path / "o.png"), "--size", "6x4", "--mask", str(rgba),
               "--guide", str(pg)) == 0
    group = toy[-1]["toy"]
    assert group.mask.shape == (4, 6) and np.allclose(group.mask, grey, atol=1 / 255)  # as --mask of a parameter
    assert np.allclose(group.guide, guide, atol=1 / 255) and group.first == 3
    # a spatial field (Method.spatial): a number, --NAME-map FILE or --transition, as for a parameter
    args = ["toy", ex, "-o", str(tmp_path / "o.png"), "--overwrite", "--size", "6x4"]
    assert run(*args, "--blend", "0.25") == 0 and toy[-1]["toy"].blend == 0.25
    assert run(*args, "--transition") == 0 and np.array_equal(toy[-1]["toy"].blend, cli.ramp((4, 6)))
    assert run(*args, "--blend", "ramp") == 0 and np.array_equal(toy[-1]["toy"].blend, cli.ramp((4, 6)))
    assert run(*args, "--blend-map", str(rgba)) == 0 and np.allclose(toy[-1]["toy"].blend, grey, atol=1 / 255)
    # an orientation field (Method.fields): a number, a .npy array or a grey image
    np.save(tmp_path / "theta.npy", grey)
    assert run(*args, "--orientation", str(tmp_path / "theta.npy")) == 0
    assert np.array_equal(toy[-1]["toy"].orientation, grey) and toy[-1]["toy"].blend == 0.5
    assert run(*args, "--orientation", "1.5") == 0 and toy[-1]["toy"].orientation == 1.5


def test_option_group_bad_value_is_exit_2_naming_the_flag(toy, tmp_path, capsys):
    ex = str(save_image(tmp_path / "ex.png", data.load("bumpy")[:8, :8]))
    out = tmp_path / "o.png"
    assert run("toy", ex, "-o", str(out), "--strength", "-1") == 2
    err = _one_line_error(capsys, 2)
    assert "--strength must be > 0, got -1" in err
    assert run("toy", ex, "-o", str(out), "--strength", "strong") == 2  # a TypeError that names no field
    assert _one_line_error(capsys, 2).startswith("texsynth: error: --strength: ")
    assert not out.exists() and not toy  # refused before the function ran


def test_a_field_name_shared_by_two_groups_fails_when_the_parser_is_built(monkeypatch):
    def clash(exemplar, size, *, toy=Toy(), other=OtherToy(), rng=None):
        """Two groups with a field ``first`` each."""

    def plain(exemplar, size, *, toy=Toy(), first=1):
        """A group's field is also a parameter."""

    for func, where in ((clash, "field of other="), (plain, "also a parameter")):
        monkeypatch.setattr(cli, "METHODS", {"toy": _ToyMethod(target="toy:clash", summary="", func=func)})
        with pytest.raises(TypeError, match=f"'first' is a .*{where}.*unique"):
            cli.build_parser()


# --------------------------------------------------------------------------- interpolate
FAST_INTERPOLATE = ["--stages", "((1, 9),)", "--max-iterations", "1", "--no-statistics-step",
                    "--max-neighborhoods", "16", "--max-feature-points", "8", "--alpha-steps", "2", "--seed", "0"]


def _flat(kwargs):
    """A call's keywords with the fields of its option groups (dataclass instances) beside them, so that a test
    reads ``mask`` whether it is a parameter or a field of ``constraints=Constraints(...)``."""
    import dataclasses

    flat = dict(kwargs)
    for value in kwargs.values():
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            flat.update({f.name: getattr(value, f.name) for f in dataclasses.fields(value) if f.name not in kwargs})
    return flat


def _spy(monkeypatch, module, name, fake=None):
    """Record the calls of module.name (the CLI looks the function up at run time), their option groups
    flattened (:func:`_flat`); ``fake`` replaces it."""
    import functools

    real = getattr(module, name)
    calls = []

    @functools.wraps(real)
    def wrapper(*args, **kwargs):
        calls.append(_flat(kwargs))
        return fake(*args, **kwargs) if fake else real(*args, **kwargs)

    monkeypatch.setattr(module, name, wrapper)
    return calls


@pytest.fixture
def pair_files(tmp_path):
    a, b = data.load("brick")[:32, :32], data.load("bumpy")[:32, :32]
    return str(save_image(tmp_path / "a.png", a)), str(save_image(tmp_path / "b.png", b))


def test_interpolate_number_alpha_end_to_end(tmp_path, pair_files, monkeypatch):
    import texsynth.optimization as interpolation

    calls = _spy(monkeypatch, interpolation, "interpolate_textures")
    out = tmp_path / "mid.png"
    assert run("interpolate-textures", *pair_files, "-o", str(out), "--alpha", "0.5", *FAST_INTERPOLATE) == 0
    assert load_image(out).shape == (32, 32, 3)
    assert calls[0]["alpha"] == 0.5 and calls[0]["size"] == (32, 32) and calls[0].get("features") is None


def test_interpolate_transition_end_to_end(tmp_path, pair_files, monkeypatch):
    import texsynth.optimization as interpolation

    calls = _spy(monkeypatch, interpolation, "interpolate_textures")
    out = tmp_path / "strip.png"
    assert run("interpolate-textures", *pair_files, "-o", str(out), "--transition", "--size", "48x24",
               *FAST_INTERPOLATE) == 0
    assert load_image(out).shape == (24, 48, 3)
    np.testing.assert_allclose(calls[0]["alpha"], interpolation.transition_alpha_map((24, 48)))


def test_interpolate_alpha_map_from_an_rgb_file_end_to_end(tmp_path, pair_files, monkeypatch):
    import texsynth.optimization as interpolation

    calls = _spy(monkeypatch, interpolation, "interpolate_textures")
    yy, xx = np.mgrid[:24, :40]
    grey = np.clip((12 - np.hypot(yy - 12, xx - 20)) / 6 + 0.5, 0, 1)  # a disc of B in A (Figure 7)
    rgba = np.concatenate([np.stack([grey] * 3, -1), np.ones((24, 40, 1))], -1)
    amap = save_image(tmp_path / "disc.png", rgba)
    out = tmp_path / "disc_out.png"
    assert run("interpolate-textures", *pair_files, "-o", str(out), "--alpha-map", str(amap), *FAST_INTERPOLATE) == 0
    assert load_image(out).shape == (24, 40, 3)  # the map's size, not the inputs'
    assert calls[0]["alpha"].shape == (24, 40) and calls[0]["size"] == (24, 40)
    np.testing.assert_allclose(calls[0]["alpha"], grey, atol=1 / 255)


def test_interpolate_features_end_to_end(tmp_path, pair_files, monkeypatch):
    import texsynth.optimization as interpolation

    calls = _spy(monkeypatch, interpolation, "interpolate_textures")
    fa = np.zeros((32, 32, 3))
    fa[::8] = 0.9  # horizontal lines in an RGB file
    fb = np.zeros((32, 32), np.uint16)
    fb[:, ::8] = 40000  # vertical lines in a 16-bit grey file (0.61 > 0.5)
    pa = save_image(tmp_path / "fa.png", fa)
    pb = tmp_path / "fb.png"
    import imageio.v3 as iio

    iio.imwrite(pb, fb)
    out = tmp_path / "feat.png"
    assert run("interpolate-textures", *pair_files, "-o", str(out), "--alpha", "0.3", "--features", str(pa), str(pb),
               *FAST_INTERPOLATE) == 0
    assert load_image(out).shape == (32, 32, 3)
    f1, f2 = calls[0]["features"]
    assert f1.dtype == bool and f2.dtype == bool and f1.shape == f2.shape == (32, 32)
    assert np.array_equal(f1, fa[..., 0] > 0.5) and np.array_equal(f2, fb > 20000)
    # feature maps of the wrong size: the function's one-line error, exit 2
    small = save_image(tmp_path / "small.png", np.zeros((8, 8)))
    assert run("interpolate-textures", *pair_files, "-o", str(tmp_path / "x.png"), "--alpha", "0.3",
               "--features", str(small), str(pb), *FAST_INTERPOLATE) == 2
    assert not (tmp_path / "x.png").exists()


def test_interpolate_alpha_options_are_exclusive_and_ramp_is_an_alias(tmp_path, pair_files, monkeypatch, capsys):
    import texsynth.optimization as interpolation

    calls = _spy(monkeypatch, interpolation, "interpolate_textures", fake=lambda a, b, alpha, size, **kw: a)
    amap = str(save_image(tmp_path / "m.png", np.zeros((8, 8))))
    out = str(tmp_path / "o.png")
    for options in (["--alpha", "0.5", "--transition"], ["--alpha-map", amap, "--transition"],
                    ["--alpha", "0.5", "--alpha-map", amap], []):
        with pytest.raises(SystemExit) as info:
            run("interpolate-textures", *pair_files, "-o", out, *options)
        err = capsys.readouterr().err
        assert info.value.code == 2 and err.count("\n") == 1, options
        assert ("not allowed with" if options else "one of the arguments --alpha --alpha-map --transition") in err
    assert run("interpolate-textures", *pair_files, "-o", out, "--alpha", "ramp", "--size", "40x8") == 0
    assert run("interpolate-textures", *pair_files, "-o", out, "--overwrite", "--transition", "--size", "40x8") == 0
    assert np.array_equal(calls[0]["alpha"], calls[1]["alpha"]) and calls[0]["alpha"].shape == (8, 40)
    # --alpha FILE is --alpha-map FILE: without --size the output has the map's size
    assert run("interpolate-textures", *pair_files, "-o", str(tmp_path / "p.png"), "--alpha", amap) == 0
    assert calls[-1]["alpha"].shape == (8, 8) and calls[-1]["size"] == (8, 8)


# --------------------------------------------------------------------------- optimize, animate
def test_optimize_with_k_coherent_candidates(tmp_path):
    ex = save_image(tmp_path / "ex.png", data.load("bumpy")[:32, :32])
    out = tmp_path / "kc.png"
    assert run("optimize-texture", str(ex), "-o", str(out), "--size", "40x40", "--candidates", "k-coherent", "--k", "2",
               "--levels", "1", "--max-iterations", "2", "--seed", "0") == 0
    assert load_image(out).shape == (40, 40, 3)
    # a clear error naming the clash, nothing written
    assert run("optimize-texture", str(ex), "-o", str(tmp_path / "bad.png"), "--candidates", "k-coherent",
               "--method", "exact") == 2
    assert not (tmp_path / "bad.png").exists()


def test_optimize_with_an_rgba_mask_and_tileable(tmp_path, monkeypatch):
    import texsynth.optimization as optimization

    calls = _spy(monkeypatch, optimization, "optimize_texture")
    ex = save_image(tmp_path / "ex.png", data.load("bumpy")[:32, :32])
    inside = np.zeros((40, 40), bool)
    inside[10:30, 10:30] = True
    mask = np.zeros((40, 40, 4))
    mask[..., 3] = 1.0  # an opaque RGBA mask, as paint programs save it
    mask[inside, :3] = 1.0
    target = np.zeros((40, 40, 3))
    target[..., 0] = 1.0  # pure red wanted inside the mask
    pm, pt = save_image(tmp_path / "mask.png", mask), save_image(tmp_path / "target.png", target)
    fast = ["--size", "40x40", "--neighborhood-sizes", "8", "--levels", "1", "--max-iterations", "2", "--seed", "0"]
    out = tmp_path / "hole.png"
    assert run("optimize-texture", str(ex), "-o", str(out), "--tileable", "--mask", str(pm), "--target", str(pt),
               "--constraint-weight", "100", *fast) == 0
    kw = calls[0]
    assert kw["tileable"] is True and kw["mask"].shape == (40, 40) and np.array_equal(kw["mask"] > 0.5, inside)
    result = load_image(out)
    assert result.shape == (40, 40, 3)
    red = result[..., 0] - result[..., 1:].mean(-1)
    assert red[inside].mean() > 0.8 and red[~inside].mean() < 0.3  # the constraint holds only inside
    # the same mask saved as a grey file gives the same output
    grey = save_image(tmp_path / "mask_grey.png", inside.astype(float))
    out2 = tmp_path / "hole2.png"
    assert run("optimize-texture", str(ex), "-o", str(out2), "--tileable", "--mask", str(grey), "--target", str(pt),
               "--constraint-weight", "100", *fast) == 0
    assert np.array_equal(load_image(out2), result)


@pytest.mark.parametrize("name, module, fast", [
    ("optimize-texture", "optimization", ["--neighborhood-sizes", "8", "--levels", "1", "--max-iterations", "1"]),
    ("synthesize-controlled", "pixel", ["--levels", "1"]),
])
def test_orientation_and_magnification_fields_from_numbers_npy_and_grey_images(tmp_path, monkeypatch, capsys, name,
                                                                               module, fast):
    import importlib

    function = "optimize_texture" if name == "optimize-texture" else "synthesize_controlled"
    calls = _spy(monkeypatch, importlib.import_module(f"texsynth.{module}"), function)
    ex = save_image(tmp_path / "ex.png", data.load("brick")[:32, :32])
    angles = np.tile(np.linspace(0, np.pi, 24), (20, 1))
    np.save(tmp_path / "theta.npy", angles)
    grey = np.tile(np.linspace(0.0, 1.0, 24), (20, 1))
    ramp = save_image(tmp_path / "ramp.png", grey, bits=16)
    args = [name, str(ex), "--size", "24x20", "--seed", "0", *fast]
    assert run(*args, "-o", str(tmp_path / "a.png"), "--orientation", "0.5", "--magnification", "1.2") == 0
    assert calls[-1]["orientation"] == 0.5 and calls[-1]["magnification"] == 1.2
    assert run(*args, "-o", str(tmp_path / "b.png"), "--orientation", str(tmp_path / "theta.npy"),
               "--magnification", str(ramp)) == 0
    assert np.array_equal(calls[-1]["orientation"], angles)
    # grey 0..1 -> magnification 0.5..2 geometrically (the documented mapping), to 16-bit rounding
    assert np.allclose(calls[-1]["magnification"], 2.0 ** (2 * grey - 1), atol=1e-4)
    assert load_image(tmp_path / "b.png").shape == (20, 24, 3)
    assert run(*args, "-o", str(tmp_path / "c.png"), "--orientation", str(ramp)) == 0
    assert np.allclose(calls[-1]["orientation"], 2 * np.pi * grey, atol=1e-3)  # grey 0..1 -> 0..2 pi
    capsys.readouterr()
    assert run(*args, "-o", str(tmp_path / "d.png"), "--magnification", str(tmp_path / "nothing.png")) == 2
    assert "--magnification must be a number, a .npy file or an image file" in capsys.readouterr().err
    np.save(tmp_path / "small.npy", angles[:5])
    assert run(*args, "-o", str(tmp_path / "e.png"), "--orientation", str(tmp_path / "small.npy")) == 2
    assert "orientation has shape (5, 24) but the output size is (20, 24)" in capsys.readouterr().err


def test_animate_named_flow_to_gif_and_frame_folder(tmp_path):
    from texsynth.io import load_frames

    ex = save_image(tmp_path / "ex.png", data.load("bumpy")[:32, :32])
    fast = ["--size", "24x20", "--n-frames", "3", "--neighborhood-sizes", "8", "--levels", "1",
            "--max-iterations", "2", "--max-frame-iterations", "1", "--seed", "0"]
    gif = tmp_path / "vortex.gif"
    assert run("animate-texture", str(ex), "-o", str(gif), "--flows", "vortex:1", *fast) == 0
    assert load_frames(gif).shape == (3, 20, 24, 3)
    folder = tmp_path / "sink"
    assert run("animate-texture", str(ex), "-o", str(folder), "--flows", "sink:1.5", *fast) == 0
    frames = sorted(p.name for p in folder.iterdir())
    assert len(frames) == 3 and all(f.endswith(".png") for f in frames)
    assert load_image(folder / frames[0]).shape == (20, 24, 3)
    assert run("animate-texture", str(ex), "-o", str(tmp_path / "n.gif"), "--flows", "swirl:1", *fast) == 2


def test_a_translation_flow_is_x_to_the_right_and_y_down():
    from texsynth._cli_values import CommandError, parse_flow

    right = parse_flow("translation:2", (4, 6))  # flows hold (d_row, d_col)
    assert np.all(right[..., 0] == 0) and np.all(right[..., 1] == 2)
    down_right = parse_flow("translation:(1, 3)", (4, 6))
    assert np.all(down_right[..., 0] == 3) and np.all(down_right[..., 1] == 1)
    with pytest.raises(CommandError, match="--flows translation"):
        parse_flow("translation:(1, 2, 3)", (4, 6))


@pytest.mark.parametrize("tty, flag, expected", [(True, [], True), (True, ["--no-progress"], False),
                                                 (False, [], False)])
def test_progress_bar_is_on_by_default_on_a_terminal(tmp_path, monkeypatch, tty, flag, expected):
    import texsynth.procedural as procedural

    import functools

    seen = {}
    real = procedural.reaction_diffusion

    @functools.wraps(real)  # the command reads the signature
    def spy(*args, **kwargs):
        seen.update(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(procedural, "reaction_diffusion", spy)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: tty)
    assert run("reaction-diffusion", "-o", str(tmp_path / "m.png"), "--size", "16x16", "--steps", "5", *flag) == 0
    assert seen["progress"] is expected


# --------------------------------------------------------------------------- failure modes (issue: reliability)
def _one_line_error(capsys, status):
    err = capsys.readouterr().err.strip()
    assert status == 2 and err.startswith("texsynth: error:") and "\n" not in err, (status, err)
    return err


@pytest.fixture
def metal_file(tmp_path):
    path = tmp_path / "metal.png"
    save_image(path, data.load("metal")[:32, :32])
    return path


def test_unwritable_folder_is_one_line(tmp_path, metal_file, capsys, monkeypatch):
    import errno

    import texsynth.core.files as files

    def refuse(path):
        raise PermissionError(errno.EACCES, "Permission denied", str(path.parent))

    monkeypatch.setattr(files, "_new_temp_file", refuse)  # a read-only folder (the tests may run as root)
    status = run("patchwork", str(metal_file), "-o", str(tmp_path / "out.png"), "--grid-spacing", "8")
    assert "Permission denied" in _one_line_error(capsys, status)
    assert not (tmp_path / "out.png").exists()


def test_full_disk_is_one_line_and_leaves_nothing(tmp_path, metal_file, capsys, monkeypatch):
    import errno

    import imageio.v3 as iio

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(iio, "imwrite", full)
    status = run("patchwork", str(metal_file), "-o", str(tmp_path / "out.png"), "--grid-spacing", "8")
    assert "No space left" in _one_line_error(capsys, status)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metal.png"]  # no output, no temporary


def test_output_naming_a_folder_is_one_line_even_with_overwrite(tmp_path, metal_file, capsys):
    (tmp_path / "folder.png").mkdir()
    status = run("patchwork", str(metal_file), "-o", str(tmp_path / "folder.png"), "--grid-spacing", "8",
                 "--overwrite")
    assert "folder" in _one_line_error(capsys, status)
    assert (tmp_path / "folder.png").is_dir()


def test_volume_outputs_are_written_as_a_set(tmp_path, metal_file, capsys):
    (tmp_path / "vol_slice_y.png").write_bytes(b"mine")
    status = run("synthesize-solid", str(metal_file), "-o", str(tmp_path / "vol.npy"), "--size", "8", "--levels", "1",
                 "--passes", "1")
    assert "vol_slice_y.png" in _one_line_error(capsys, status)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metal.png", "vol_slice_y.png"]  # nothing written
    assert (tmp_path / "vol_slice_y.png").read_bytes() == b"mine"


def test_unwritable_format_is_refused_before_the_synthesis(tmp_path, metal_file, capsys, monkeypatch):
    import functools

    import texsynth.optimization as optimization

    @functools.wraps(optimization.animate_texture)  # the command reads the signature
    def never(*args, **kwargs):
        raise AssertionError("the synthesis ran before the output path was checked")

    monkeypatch.setattr(optimization, "animate_texture", never)
    status = run("animate-texture", str(metal_file), "-o", str(tmp_path / "frames.tif"), "--size", "16",
                 "--flows", "rotation:0.1", "--n-frames", "2")
    assert "frame-sequence format" in _one_line_error(capsys, status)


def test_empty_size_is_an_error_not_ignored(tmp_path, metal_file, capsys):
    status = run("patchwork", str(metal_file), "-o", str(tmp_path / "out.png"), "--size", "")
    assert "--size" in _one_line_error(capsys, status)
    assert not (tmp_path / "out.png").exists()


def test_version(capsys):
    import texsynth

    with pytest.raises(SystemExit) as stop:
        run("--version")
    assert stop.value.code == 0 and capsys.readouterr().out.strip() == f"texsynth {texsynth.__version__}"


def test_sigterm_during_the_write_leaves_nothing(tmp_path, metal_file):
    """`timeout` (SIGTERM) while the command writes: no hidden partial file, the process ends by SIGTERM."""
    import signal
    import textwrap
    import time

    out = tmp_path / "out.png"
    code = textwrap.dedent(f"""
        import time
        from texsynth import cli
        from texsynth.io import _images
        def slow(path, *args, **kwargs):
            open(path, "wb").write(b"partial")
            print("writing", flush=True)
            time.sleep(30)
        _images.imwrite = slow  # writes the encoded image to the temporary file
        cli.main(["patchwork", {str(metal_file)!r}, "-o", {str(out)!r}, "--grid-spacing", "8", "--no-progress"])
        """)
    with subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True) as proc:
        assert proc.stdout.readline().strip() == "writing"
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=120) == -signal.SIGTERM  # a hang guard, not a time bound
    time.sleep(0.1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metal.png"]  # no out.png, no .out-XXXX.png


def test_outputs_get_the_umask_permissions(tmp_path, metal_file):
    import os
    import stat

    old = os.umask(0o022)
    try:
        assert run("patchwork", str(metal_file), "-o", str(tmp_path / "out.png"), "--grid-spacing", "8") == 0
        assert stat.S_IMODE((tmp_path / "out.png").stat().st_mode) == 0o644
        os.chmod(tmp_path / "out.png", 0o640)
        assert run("patchwork", str(metal_file), "-o", str(tmp_path / "out.png"), "--grid-spacing", "8",
                   "--overwrite") == 0
        assert stat.S_IMODE((tmp_path / "out.png").stat().st_mode) == 0o640  # a replaced file keeps its mode
    finally:
        os.umask(old)


def test_sixteen_bits_in_sixteen_bits_out_unless_told(tmp_path, capsys):
    from texsynth.io import image_bits

    albedo = data.load("bread")[:48, :48]
    deep = (np.random.default_rng(0).random((48, 48, 3)) * 65535).astype(np.uint16)  # no 8-bit values
    source = save_image(tmp_path / "albedo16.png", deep, bits=16)
    assert run("quilt", str(source), "-o", str(tmp_path / "q.png"), "--size", "64x56", "--seed", "0",
               "--block", "16") == 0
    out = load_image(tmp_path / "q.png")
    assert image_bits(tmp_path / "q.png") == 16
    # quilting copies pixels: every output value is one of the input's 16-bit values, exactly
    import texsynth

    assert np.array_equal(out, texsynth.quilt(deep / 65535.0, (56, 64), block=16, rng=0))
    assert run("quilt", str(source), "-o", str(tmp_path / "q8.png"), "--size", "64x56", "--bits", "8") == 0
    assert image_bits(tmp_path / "q8.png") == 8
    assert run("quilt", str(source), "-o", str(tmp_path / "q.tif"), "--size", "64x56", "--bits", "32") == 0
    assert image_bits(tmp_path / "q.tif") == 32
    assert run("quilt", str(source), "-o", str(tmp_path / "q.jpg"), "--size", "64x56") == 0  # JPEG: 8 bits
    assert run("quilt", str(save_image(tmp_path / "a8.png", albedo)), "-o", str(tmp_path / "e.png")) == 0
    assert image_bits(tmp_path / "e.png") == 8
    capsys.readouterr()
    assert run("quilt", str(source), "-o", str(tmp_path / "bad.png"), "--bits", "32") == 2
    assert "--bits 32" in capsys.readouterr().err and not (tmp_path / "bad.png").exists()


def test_channels_are_rendered_through_the_map_and_written_as_a_set(tmp_path, capsys):
    import texsynth

    albedo = data.load("bread")[:48, :48]
    height = (albedo.mean(-1) * 65535).astype(np.uint16)
    gy, gx = np.gradient(albedo.mean(-1))
    normal = np.stack([-4 * gx, 4 * gy, np.ones_like(gx)], -1)
    normal = (normal / np.linalg.norm(normal, axis=-1, keepdims=True) + 1) / 2
    files = [save_image(tmp_path / "albedo.png", albedo), save_image(tmp_path / "height.png", height, bits=16),
             save_image(tmp_path / "normal.png", normal, bits=16)]
    argv = ["patch-sampling", str(files[0]), "-o", str(tmp_path / "out.png"), "--size", "64x64", "--seed", "0",
            "--block", "16", "--channels", str(files[1]), "--normal-maps", str(files[2])]
    assert run(*argv) == 0
    out, info = texsynth.patch_sampling(albedo, 64, block=16, rng=0, return_info=True)
    assert np.abs(load_image(tmp_path / "out.png") - out).max() <= 0.5 / 255 + 1e-9
    rendered_height = load_image(tmp_path / "out_height.png")  # 16 bits in, 16 bits out
    expected = texsynth.apply_coordinates(height, info) / 65535.0
    assert np.abs(rendered_height - expected).max() <= 1.5 / 65535
    n = load_image(tmp_path / "out_normal.png") * 2 - 1
    assert np.abs(np.linalg.norm(n, axis=-1) - 1).max() < 1e-3
    # a channel of the wrong size is refused before the synthesis, and nothing is written
    small = save_image(tmp_path / "small.png", albedo[:40])
    capsys.readouterr()
    argv[argv.index("-o") + 1] = str(tmp_path / "other.png")
    assert run(*argv[:-4], "--channels", f"{files[1]},{small}") == 2
    assert "small.png" in capsys.readouterr().err and not list(tmp_path.glob("other*"))
    # an existing channel output is refused (nothing written) unless --overwrite
    assert run(*argv) == 0 and run(*argv) == 2
    assert run(*argv, "--overwrite") == 0


def test_a_video_map_is_saved_with_the_frames_and_applied_later(tmp_path, capsys):
    """patchwork-video --coordinates writes the video map with the frames (both or neither); apply-coordinates
    renders a channel's frames through it: the input frames give the video back, to 8-bit rounding."""
    from texsynth.io import load_frames, save_frames

    water = data.load("water")[:48, :48]
    clip = save_frames(tmp_path / "clip", np.stack([np.roll(water, 2 * t, axis=1) for t in range(5)]))
    out, the_map = tmp_path / "out", tmp_path / "map.npz"
    argv = ["patchwork-video", str(clip), "-o", str(out), "--size", "32x32", "--n-frames", "4", "--grid-spacing", "16",
            "--seed", "0", "--coordinates", str(the_map)]
    assert run(*argv) == 0
    assert np.load(the_map)["coordinates"].shape[:3] == (4, 32, 32)
    again = tmp_path / "again"
    assert run("apply-coordinates", str(the_map), str(clip), "-o", str(again)) == 0
    # the video clips to [0, 1] and drops cells below 1/512 (as the map does not): measured 1/255 at most
    assert np.abs(load_frames(again) - load_frames(out)).max() <= 2 / 255
    capsys.readouterr()
    assert run("apply-coordinates", str(the_map), str(clip), str(clip), "-o", str(tmp_path / "x")) == 2
    assert "video map" in capsys.readouterr().err and not (tmp_path / "x").exists()
    # a frame output that cannot be written leaves no map behind
    (tmp_path / "blocked").mkdir()
    (tmp_path / "blocked" / "mine.txt").write_text("not a frame")
    assert run(*argv[:3], str(tmp_path / "blocked"), *argv[4:-1], str(tmp_path / "map2.npz"), "--overwrite") == 2
    assert not (tmp_path / "map2.npz").exists()


def test_coordinates_are_saved_and_applied_later(tmp_path, capsys):
    """--coordinates MAP.npz is written with the output; apply-coordinates renders a channel through it exactly
    as --channels did. A mixture takes one channel file per input (joined by '+'); seam carving blends."""
    a, b = data.load("bread")[:24, :24], data.load("wood")[:28, :28]
    files = [save_image(tmp_path / n, im, bits=16) for n, im in
             (("a.png", a), ("b.png", b), ("ha.png", a.mean(-1)), ("hb.png", b.mean(-1)))]
    out, the_map = tmp_path / "mix.png", tmp_path / "mix_map.npz"
    argv = ["mix-textures", str(files[0]), str(files[1]), "-o", str(out), "--size", "24x20", "--seed", "0",
            "--levels", "1", "--weights", "ramp", "--channels", f"{files[2]}+{files[3]}", "--coordinates", str(the_map)]
    assert run(*argv) == 0
    saved = np.load(the_map)
    assert saved["coordinates"].shape == (20, 24, 2, 2) and saved["source_index"].shape == (20, 24, 2)
    assert np.allclose(saved["weights"].sum(-1), 1)
    later = tmp_path / "later.png"
    assert run("apply-coordinates", str(the_map), str(files[2]), str(files[3]), "-o", str(later)) == 0
    assert np.array_equal(load_image(later), load_image(tmp_path / "mix_ha.png"))
    # the grey channel through the map is the grey of the (16-bit) output, to rounding
    assert np.abs(load_image(later) - load_image(out).mean(-1)).max() < 2e-4
    capsys.readouterr()
    assert run("apply-coordinates", str(the_map), str(files[2]), "-o", str(tmp_path / "x.png")) == 2
    assert "1 image" in capsys.readouterr().err and not (tmp_path / "x.png").exists()
    assert run(*argv[:-4], "--channels", str(files[2]), "-o", str(tmp_path / "y.png")) == 2  # one file, 2 inputs
    assert "join one file per input" in capsys.readouterr().err
    # seam carving: inserted seams blend, removal copies; the map is applied as --channels did
    photo = save_image(tmp_path / "photo.png", data.load("brick")[:40, :48])
    height = save_image(tmp_path / "h.png", data.load("brick")[:40, :48].mean(-1))
    argv = ["carve-seams", str(photo), "-o", str(tmp_path / "wide.png"), "--size", "60x40", "--channels",
            str(height), "--coordinates", str(tmp_path / "wide.npz")]
    assert run(*argv) == 0
    assert np.load(tmp_path / "wide.npz")["weights"].shape[:2] == (40, 60)
    assert run("apply-coordinates", str(tmp_path / "wide.npz"), str(height), "-o", str(tmp_path / "h2.png")) == 0
    assert np.array_equal(load_image(tmp_path / "h2.png"), load_image(tmp_path / "wide_h.png"))
    assert run(*argv) == 2 and "exists" in capsys.readouterr().err  # the map is an output like the others
    assert run("quilt", str(photo), "-o", str(tmp_path / "q.png"), "--coordinates", str(tmp_path / "q.npy")) == 2
    assert ".npz" in capsys.readouterr().err and not (tmp_path / "q.png").exists()


# --------------------------------------------------------------------------- geometry
def test_geometry_from_a_mesh_file_to_a_mesh_file_where_the_example_was(tmp_path, capsys):
    """A closed mesh in, a larger mesh out in the example's units and place, and a preview."""
    from texsynth.geometry import sdf_to_mesh
    from texsynth.surface import read_mesh, write_mesh

    vertices, faces = sdf_to_mesh(data.volume("pebbles", 24))
    write_mesh(tmp_path / "pebbles.ply", (vertices * 0.01 + 5.0, faces))  # centimetres, away from the origin
    argv = ["geometry", str(tmp_path / "pebbles.ply"), "-o", str(tmp_path / "out.obj"), "--voxels", "24",
            "--size", "32", "--block", "8", "-s", "0", "--preview", str(tmp_path / "look.png")]
    assert run(*argv) == 0
    out = read_mesh(tmp_path / "out.obj")
    low = out.vertices.min(0)
    assert np.all(np.abs(low - 5.0) < 0.06)  # where the example was (not at 0), within a few voxels of 0.01
    assert 0.25 < (out.vertices.max(0) - low).max() < 0.4  # 32 voxels of about 0.01 (the example's 24)
    assert load_image(tmp_path / "look.png").shape[:2] == (768, 768)
    assert run(*argv) == 2 and "exists" in capsys.readouterr().err  # nothing overwritten by surprise


def test_geometry_volumes_sizes_and_refusals(tmp_path, capsys):
    volume = tmp_path / "plate.npy"
    example = data.volume("plate", 24)
    np.save(volume, example)
    assert run("geometry", str(volume), "-o", str(tmp_path / "out.npy"), "--size", "40x32x16", "-s", "0") == 0
    assert np.load(tmp_path / "out.npy").shape == (16, 32, 40)  # WxHxD -> (depth, height, width)
    assert run("geometry", str(volume), "-o", str(tmp_path / "twice.npy"), "-s", "0") == 0
    assert np.load(tmp_path / "twice.npy").shape == tuple(2 * n for n in example.shape)  # the default: twice
    for argv, words in ((["--size", "40x32"], "WxHxD"), ([], "must be a mesh")):
        target = tmp_path / ("bad.npy" if argv else "bad.png")
        err = _one_line_error(capsys, run("geometry", str(volume), "-o", str(target), *argv))
        assert words in err and not target.exists()
    mesh = tmp_path / "open.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n")
    err = _one_line_error(capsys, run("geometry", str(mesh), "-o", str(tmp_path / "o.ply"), "--voxels", "8"))
    assert "not closed" in err and not (tmp_path / "o.ply").exists()


def test_geometry_analogies_from_volumes_to_a_mesh(tmp_path, capsys):
    """The cylinder pair's grooves carried to another cylinder: a mesh out, every input refused as the output."""
    from texsynth.surface import read_mesh

    for name, volume in (("a", data.volume("cylinder", 24)), ("ap", data.volume("grooved_cylinder", 24))):
        np.save(tmp_path / f"{name}.npy", volume[:16])
    inputs = ["geometry-analogies", str(tmp_path / "a.npy"), str(tmp_path / "ap.npy"), "cylinder", "--size", "24"]
    argv = inputs + ["-o", str(tmp_path / "out.ply"), "--levels", "1", "-s", "0"]
    assert run(*argv) == 0
    out = read_mesh(tmp_path / "out.ply")
    assert np.ptp(out.vertices[:, 2]) > 16  # the whole of b (24 voxels deep), not the example's 16 slices
    err = _one_line_error(capsys, run(*inputs, "-o", str(tmp_path / "a.npy"), "--overwrite"))
    assert "also an input" in err
    err = _one_line_error(capsys, run(*inputs, "--field-b", "sideways", "-o", str(tmp_path / "o.ply")))
    assert "field" in err and not (tmp_path / "o.ply").exists()


def test_btf_on_the_plane_and_over_a_mesh(tmp_path, capsys):
    from texsynth.surface import read_mesh, sphere, write_mesh

    sample = data.btf("stones", 64, n_lights=8)
    np.savez(tmp_path / "s.npz", images=sample.images, lights=sample.lights)
    base = ["btf", str(tmp_path / "s.npz"), "--n-textons", "8", "-s", "0"]
    assert run(*base, "-o", str(tmp_path / "out.npz"), "--size", "72x66", "--preview", str(tmp_path / "p.png")) == 0
    with np.load(tmp_path / "out.npz") as out:
        assert out["images"].shape == (8, 66, 72) and np.allclose(out["lights"], sample.lights)
    assert load_image(tmp_path / "p.png").shape[:2] == (66, 288)  # four lights side by side
    write_mesh(tmp_path / "ball.ply", sphere(642))
    assert run(*base, "--mesh", str(tmp_path / "ball.ply"), "-o", str(tmp_path / "lit.ply"), "--n-vertices", "600",
               "--light", "0,0,1") == 0
    lit = read_mesh(tmp_path / "lit.ply")
    grey = lit.colors[:, 0]
    assert grey[lit.vertices[:, 2] > 0.5].mean() > grey[lit.vertices[:, 2] < -0.5].mean() + 0.1  # lit from above
    for argv, words in (([], "must be a BTF"), (["--mesh", str(tmp_path / "ball.ply")], "must be a mesh")):
        err = _one_line_error(capsys, run(*base, *argv, "-o", str(tmp_path / "out.png")))
        assert words in err


def test_mesh_quilting_bundled_swatch_over_a_surface_file(tmp_path, capsys):
    """A bundled swatch by name over a mesh file: the surface and its elements, every element whole."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from texsynth.surface import read_mesh, sphere, write_mesh

    ball = sphere(2562)
    write_mesh(tmp_path / "ball.ply", ball)
    argv = ["mesh-quilting", "rivets", str(tmp_path / "ball.ply"), "-o", str(tmp_path / "out.ply"), "-s", "0"]
    assert run(*argv, "--elements-only") == 0
    out = read_mesh(tmp_path / "out.ply")
    edges = np.concatenate([out.faces[:, [0, 1]], out.faces[:, [1, 2]]])
    n = len(out.vertices)
    elements = connected_components(coo_matrix((np.ones(len(edges)), edges.T), shape=(n, n)), directed=False)[0]
    assert 100 <= elements <= 300  # the default unit length aims at about 200 elements over the surface
    assert np.all(np.linalg.norm(out.vertices, axis=1) > 0.98)  # on the sphere's outside, in its shell
    assert run(*argv) == 2 and "exists" in capsys.readouterr().err
    assert run(*argv, "--overwrite") == 0  # with the surface: its vertices first
    assert len(read_mesh(tmp_path / "out.ply").vertices) == len(ball.vertices) + n
    err = _one_line_error(capsys, run("mesh-quilting", "rivets", "bumpy", "-o", str(tmp_path / "out.png")))
    assert "must be a mesh" in err


# --------------------------------------------------------------------------- surface
def test_surface_follows_files_outside_the_mesh_folder_only_with_allow_outside(tmp_path, monkeypatch, capsys):
    import texsynth.surface

    (tmp_path / "x.mtl").write_text("newmtl m\nKd 1 0 0\n")
    (tmp_path / "mesh").mkdir()
    mesh = tmp_path / "mesh" / "m.obj"
    mesh.write_text("mtllib ../x.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n")
    exemplar = save_image(tmp_path / "ex.png", data.load("bread")[:16, :16])
    reads = _spy(monkeypatch, texsynth.surface, "read_mesh")
    _spy(monkeypatch, texsynth.surface, "synthesize_surface", lambda mesh, exemplar, **kwargs: mesh)  # the read only
    argv = ["surface", str(mesh), str(exemplar), "-o", str(tmp_path / "out.ply")]
    err = _one_line_error(capsys, run(*argv))
    assert "mtllib '../x.mtl' is outside the mesh's folder" in err and not (tmp_path / "out.ply").exists()
    assert run(*argv, "--allow-outside") == 0 and (tmp_path / "out.ply").exists()
    assert [call["allow_outside"] for call in reads] == [False, True]
    with pytest.raises(SystemExit):
        run("surface", "-h")
    assert "--allow-outside follow the files MESH names" in " ".join(capsys.readouterr().out.split())


def test_surface_progressive_mode_blends_two_exemplars_along_an_axis(tmp_path, capsys):
    from texsynth.surface import read_mesh, sphere, write_mesh

    write_mesh(tmp_path / "ball.ply", sphere(642))
    a = save_image(tmp_path / "a.png", np.full((40, 40, 3), 0.1))  # dark where z is lowest
    b = save_image(tmp_path / "b.png", np.full((40, 40, 3), 0.9))  # light where z is highest
    base = ["surface", str(tmp_path / "ball.ply"), str(a), "-o", str(tmp_path / "out.ply"), "--mode", "progressive"]
    err = _one_line_error(capsys, run(*base))
    assert "--exemplar-b" in err and not (tmp_path / "out.ply").exists()
    assert run(*base, "--exemplar-b", str(b), "--n-vertices", "600", "--levels", "2", "-s", "0") == 0
    out = read_mesh(tmp_path / "out.ply")
    grey, z = out.colors[:, :3].mean(axis=1), out.vertices[:, 2]
    assert grey[z < -0.6].mean() < 0.3 and grey[z > 0.6].mean() > 0.7
    err = _one_line_error(capsys, run("surface", str(tmp_path / "ball.ply"), str(a), "-o", str(tmp_path / "o.ply"),
                                      "--exemplar-b", str(b)))
    assert "--mode progressive" in err


def test_feature_aligned_on_a_creased_mesh_and_on_drawn_curves(tmp_path):
    """The surface mode finds the crests by itself; the planar command takes the curves as a second image."""
    from texsynth.surface import Mesh, read_mesh, sphere, write_mesh

    ball = sphere(2562)
    v = ball.vertices
    phi = np.arctan2(v[:, 1], v[:, 0])  # four sharp crests along meridians
    v = v * (1 + 0.25 * (1 - np.abs(np.sin(2 * phi))) * np.sqrt(np.clip(1 - v[:, 2] ** 2, 0, 1)))[:, None]
    write_mesh(tmp_path / "crease.ply", Mesh(v * [1, 1, 0.7], ball.faces))
    brick = save_image(tmp_path / "brick.png", data.load("brick"))
    assert run("surface", str(tmp_path / "crease.ply"), str(brick), "-o", str(tmp_path / "out.ply"), "--mode",
               "feature-aligned", "--n-vertices", "1500", "--levels", "2", "-s", "0") == 0
    assert len(read_mesh(tmp_path / "out.ply").colors) > 1000
    from texsynth.surface import torus

    ring = torus(2500)  # no sharp ridge: the curves are given, the vertices of its outer equator
    write_mesh(tmp_path / "ring.ply", ring)
    np.save(tmp_path / "equator.npy", np.abs(ring.vertices[:, 2]) < 0.03)
    assert run("surface", str(tmp_path / "ring.ply"), str(brick), "-o", str(tmp_path / "ring_out.ply"), "--mode",
               "feature-aligned", "--curves", str(tmp_path / "equator.npy"), "--n-vertices", "1500", "--levels", "2",
               "-s", "0") == 0
    curves = np.zeros((48, 48, 3))
    curves[4:44, 24] = 1.0  # drawn in colour: the channels are averaged
    save_image(tmp_path / "curves.png", curves)
    assert run("feature-aligned-texture", str(brick), str(tmp_path / "curves.png"), "-o", str(tmp_path / "f.png"),
               "--levels", "1", "--max-iterations", "2", "-s", "0") == 0
    assert load_image(tmp_path / "f.png").shape[:2] == (48, 48)


def test_surface_preview_is_checked_before_the_synthesis(tmp_path, monkeypatch, capsys):
    import texsynth.surface

    mesh = tmp_path / "m.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    exemplar = save_image(tmp_path / "ex.png", data.load("bread")[:16, :16])
    calls = _spy(monkeypatch, texsynth.surface, "lapped_textures", lambda mesh, exemplar, **kwargs: mesh)
    base = ["surface", str(mesh), str(exemplar), "-o", str(tmp_path / "out.obj"), "--mode", "lapped"]
    # the texture write_mesh puts beside out.obj is out.png: a preview of that name is refused, nothing written
    err = _one_line_error(capsys, run(*base, "--preview", str(tmp_path / "out.png")))
    assert "--preview" in err and "out_preview.png" in err and not (tmp_path / "out.obj").exists()
    (tmp_path / "p.png").write_bytes(b"old")
    err = _one_line_error(capsys, run(*base, "--preview", str(tmp_path / "p.png")))
    assert "pass --overwrite" in err and "overwrite=True" not in err and not (tmp_path / "out.obj").exists()
    assert not calls and (tmp_path / "p.png").read_bytes() == b"old"


def test_a_file_in_the_way_is_named_with_the_overwrite_flag(tmp_path, monkeypatch, capsys):
    import texsynth.surface

    mesh = tmp_path / "m.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    exemplar = save_image(tmp_path / "ex.png", data.load("bread")[:16, :16])
    calls = _spy(monkeypatch, texsynth.surface, "lapped_textures", lambda mesh, exemplar, **kwargs: mesh)
    (tmp_path / "out.png").write_bytes(b"old")  # the texture lapped textures would write beside out.obj
    err = _one_line_error(capsys, run("surface", str(mesh), str(exemplar), "-o", str(tmp_path / "out.obj"),
                                      "--mode", "lapped"))
    assert "out.png" in err and "pass --overwrite" in err and not calls

    def in_the_way(path, mesh, overwrite=False):  # a file the library finds in the way
        raise FileExistsError(f"{str(path)!r} already exists; pass overwrite=True to replace it")

    monkeypatch.setattr(texsynth.surface, "write_mesh", in_the_way)
    _spy(monkeypatch, texsynth.surface, "synthesize_surface", lambda mesh, exemplar, **kwargs: mesh)
    err = _one_line_error(capsys, run("surface", str(mesh), str(exemplar), "-o", str(tmp_path / "v.ply")))
    assert "pass --overwrite" in err and "overwrite=True" not in err


# --------------------------------------------------------------------------- traps of issue 34
def test_size_is_wxh_n_or_a_factor_of_the_input(tmp_path, capsys):
    assert cli.parse_size("4x", (96, 128)) == (384, 512)
    assert cli.parse_size("1.5x", (77, 96)) == (116, 144)  # rounded to whole pixels
    assert cli.parse_size("0.5X", (10, 11)) == (5, 6)
    assert cli.parse_size("64") == (64, 64)
    for bad in ("4x", "x4", "1.5", "-2x", "4y"):  # no input for the factor, or no form at all
        with pytest.raises(cli.CommandError) as info:
            cli.parse_size(bad)
        assert "--size" in str(info.value) and ("WIDTHxHEIGHT" in str(info.value)), bad
    with pytest.raises(cli.CommandError, match=r"one number N \(NxN\) or a factor of the input's size \(4x, 1.5x\)"):
        cli.parse_size("big", (8, 8))  # the error says the three forms
    with pytest.raises(cli.CommandError, match="smaller than a pixel"):
        cli.parse_size("0x", (8, 8))
    src = save_image(tmp_path / "in.png", data.load("brick")[:40, :48])
    assert run("quilt", str(src), "-o", str(tmp_path / "twice.png"), "--size", "2x", "-s", "0", "--block", "12") == 0
    assert load_image(tmp_path / "twice.png").shape == (80, 96, 3)
    assert run("uncrop", str(src), "-o", str(tmp_path / "wider.png"), "--size", "1.5x", "-s", "0",
               "--neighborhood-sizes", "8", "--levels", "1", "--max-iterations", "1") == 0
    assert load_image(tmp_path / "wider.png").shape == (60, 72, 3)
    # a factor needs an input: a procedural method says which forms it takes instead
    err = _one_line_error(capsys, run("perlin", "-o", str(tmp_path / "p.png"), "--size", "4x"))
    assert "--size 4x is a factor of the input's size" in err and "WIDTHxHEIGHT" in err
    with pytest.raises(SystemExit):
        run("optimize-texture", "--help")
    assert "a factor of the input's size (4x, 1.5x)" in " ".join(capsys.readouterr().out.split())


def test_scale_is_refused_and_magnification_is_the_elements_size(tmp_path, monkeypatch, capsys):
    # `optimize-texture --scale 4` used to be accepted as the element-magnification field: the output stayed
    # the input's size with bricks 4x larger. Now --scale is no option; the error names --size 4x and
    # --magnification, and options are never abbreviated (heeger-bergen's --scales took --scale).
    import texsynth.optimization
    import texsynth.statistical

    src = str(save_image(tmp_path / "in.png", data.load("brick")[:32, :32]))
    sizes = []
    calls = _spy(monkeypatch, texsynth.optimization, "optimize_texture",
                 lambda exemplar, size, **kwargs: sizes.append(size) or np.zeros(tuple(size) + (3,)))
    hb = _spy(monkeypatch, texsynth.statistical, "heeger_bergen", lambda exemplar, size, **kwargs: np.zeros(size))
    for name, hint in (("optimize-texture", "--magnification makes the elements larger"),
                       ("heeger-bergen", "did you mean --scales?")):
        with pytest.raises(SystemExit) as info:
            run(name, src, "-o", str(tmp_path / "o.png"), "--scale", "4")
        err = capsys.readouterr().err
        assert info.value.code == 2 and err.count("\n") == 1, err
        assert "unrecognized arguments: --scale 4" in err and "--size 4x makes the output four times" in err
        assert hint in err
    with pytest.raises(SystemExit):
        run("heeger-bergen", src, "-o", str(tmp_path / "o.png"), "--iter", "1")  # no abbreviations
    assert "--iter: did you mean --iterations?" in capsys.readouterr().err
    assert not calls and not hb
    assert run("optimize-texture", src, "-o", str(tmp_path / "m.png"), "--magnification", "2") == 0
    assert calls[-1]["magnification"] == 2 and calls[-1]["orientation"] is None
    assert sizes[-1] == (32, 32) and load_image(tmp_path / "m.png").shape == (32, 32, 3)
    assert run("optimize-texture", src, "-o", str(tmp_path / "s.png"), "--size", "4x") == 0
    assert sizes[-1] == (128, 128) and "fields" not in calls[-1]


def test_one_name_one_meaning_for_the_magnification():
    import inspect

    import texsynth
    from texsynth.core.em import Fields

    assert [f.name for f in dataclasses.fields(Fields)] == ["orientation", "magnification"]
    assert "magnification" in inspect.signature(texsynth.synthesize_controlled).parameters
    assert "scale" not in inspect.signature(texsynth.synthesize_controlled).parameters
    for name, method in cli.METHODS.items():
        assert "scale" not in method.fields, name
    with pytest.raises(ValueError, match="magnification must be positive"):
        texsynth.synthesize_controlled(data.load("brick")[:16, :16], 12, magnification=0.0)


def test_help_is_the_first_sentence_and_help_full_the_whole_text(capsys):
    with pytest.raises(SystemExit) as info:
        run("optimize-texture", "--help")
    assert info.value.code == 0
    short = " ".join(capsys.readouterr().out.split())
    with pytest.raises(SystemExit) as info:
        run("optimize-texture", "--help-full")
    assert info.value.code == 0
    full = " ".join(capsys.readouterr().out.split())
    first = "EM iterations per (level, size) stage at most; a stage also stops when the matched exemplar " \
            "neighbourhoods no longer change. (default: 5)"
    assert first in short and "They are the paper's {z_p}" not in short
    assert "They are the paper's {z_p}" in full and "usually 3-5 iterations" in full
    assert "--help-full" in short and "docs/methods/kwatra.md" in short  # where the rest is
    assert len(full) > 1.5 * len(short)
    # the short help of every method is free of the numpydoc jargon that leaked (z_p, FIELD_MIN_VALUES) and of
    # pointers to docstring sections the command line does not show
    for name in cli.METHODS:
        with pytest.raises(SystemExit):
            run(name, "--help")
        text = capsys.readouterr().out
        for jargon in ("z_p", "FIELD_MIN_VALUES", "(1 + 2)-approximate", "see Notes", ":func:", "``"):
            assert jargon not in text, (name, jargon)
    from texsynth._cli_text import first_sentence

    assert first_sentence("A (e.g. 3 px). B.") == "A (e.g. 3 px)."
    assert first_sentence("Weight of Kwatra et al. 2005, 0.5 or texsynth.core.x. More.") == \
        "Weight of Kwatra et al. 2005, 0.5 or texsynth.core.x."


def test_errors_of_the_function_name_the_flags(tmp_path, capsys):
    src = str(save_image(tmp_path / "in.png", data.load("brick")[:32, :32]))
    out = str(tmp_path / "o.png")
    err = _one_line_error(capsys, run("quilt", src, "-o", out, "--block", "500"))
    assert "pass --block <= 32" in err and "block 500" not in err.replace("--block 500", "")
    err = _one_line_error(capsys, run("optimize-texture", src, "-o", out, "--levels", "0"))
    assert "--levels must be" in err
    err = _one_line_error(capsys, run("optimize-texture", src, "-o", out, "--neighborhood-sizes", "64"))
    assert "pass --neighborhood-sizes" in err
    err = _one_line_error(capsys, run("optimize-texture", src, "-o", out, "--magnification", "0"))
    assert err.startswith("texsynth: error: --magnification must be positive")
    assert not (tmp_path / "o.png").exists()
    # ordinary words stay words; names inside a Python expression stay Python
    assert cli._flags_in("at all levels the block of k pixels", ["levels", "block", "k"]) == \
        "at all levels the block of k pixels"
    assert cli._flags_in("k=3 but pass search=Search(k=2, method='exact')", ["k", "method"]) == \
        "--k=3 but pass search=Search(k=2, method='exact')"


def test_s_is_short_for_seed(tmp_path, monkeypatch):
    import texsynth.patch

    src = str(save_image(tmp_path / "in.png", data.load("brick")[:32, :32]))
    calls = _spy(monkeypatch, texsynth.patch, "quilt", lambda exemplar, size, **kwargs: np.zeros(tuple(size) + (3,)))
    assert run("quilt", src, "-o", str(tmp_path / "a.png"), "-s", "7") == 0
    assert run("quilt", src, "-o", str(tmp_path / "b.png"), "--seed", "7") == 0
    assert calls[0]["rng"] == calls[1]["rng"] == 7
    parser = cli.build_parser()
    assert parser.parse_args(["demo", "-s", "3"]).seed == 3
    assert parser.parse_args(["surface", "m.obj", "e.png", "-o", "o.ply", "-s", "4"]).seed == 4


@pytest.fixture
def hole_files(tmp_path):
    """An image, a white hole (white = fill) and the same hole drawn black (Embark's way), and an RGBA image
    whose transparent pixels are that hole."""
    image = data.load("bread")[:48, :48]
    hole = np.zeros((48, 48)); hole[16:30, 14:34] = 1.0
    rgba = np.concatenate([image, 1.0 - hole[..., None]], -1)
    return {"image": str(save_image(tmp_path / "im.png", image)), "white": str(save_image(tmp_path / "w.png", hole)),
            "black": str(save_image(tmp_path / "b.png", 1.0 - hole)), "rgba": str(save_image(tmp_path / "a.png", rgba)),
            "hole": hole > 0.5}


FAST_INPAINT = ["--neighborhood-sizes", "8", "--levels", "1", "--max-iterations", "1", "-s", "0"]


def test_hole_is_white_and_invert_mask_takes_a_black_one(tmp_path, hole_files, capsys):
    with pytest.raises(SystemExit):
        run("inpaint", "--help")
    assert "image file, white (> 0.5) = fill" in " ".join(capsys.readouterr().out.split())
    assert run("inpaint", hole_files["image"], "--hole", hole_files["white"], "-o", str(tmp_path / "w_out.png"),
               *FAST_INPAINT) == 0
    assert run("inpaint", hole_files["image"], "--hole", hole_files["black"], "--invert-mask",
               "-o", str(tmp_path / "b_out.png"), *FAST_INPAINT) == 0
    assert np.array_equal(load_image(tmp_path / "w_out.png"), load_image(tmp_path / "b_out.png"))
    capsys.readouterr()
    # the black hole without --invert-mask fills 88 % of the photograph: a warning names the share and the fix
    assert run("inpaint", hole_files["image"], "--hole", hole_files["black"], "-o", str(tmp_path / "x.png"),
               *FAST_INPAINT) == 0
    err = capsys.readouterr().err
    assert "texsynth: warning: the hole covers 88 % of the image" in err and "--invert-mask" in err
    err = _one_line_error(capsys, run("optimize-texture", hole_files["image"], "-o", str(tmp_path / "y.png"),
                                      "--invert-mask"))
    assert "--invert-mask inverts the --mask file; pass --mask FILE too" in err


def test_invert_mask_inverts_the_commands_main_mask_only(tmp_path, hole_files, monkeypatch):
    import texsynth.optimization

    calls = _spy(monkeypatch, texsynth.optimization, "inpaint", lambda image, hole, **kwargs: np.asarray(image))
    assert run("inpaint", hole_files["image"], "--hole", hole_files["black"], "--sample-mask", hole_files["black"],
               "--invert-mask", "-o", str(tmp_path / "o.png")) == 0
    assert np.allclose(calls[-1]["hole"], hole_files["hole"]) and np.allclose(calls[-1]["sample_mask"],
                                                                              ~hole_files["hole"])
    for name, method in cli.METHODS.items():
        if method.mask is not None:
            assert method.mask in method.maps, name


def test_hole_channel_a_takes_the_inputs_transparency(tmp_path, hole_files, monkeypatch, capsys):
    import texsynth.optimization

    real = texsynth.optimization.inpaint
    calls = _spy(monkeypatch, texsynth.optimization, "inpaint")
    assert run("inpaint", hole_files["rgba"], "--hole-channel", "a", "-o", str(tmp_path / "filled.png"),
               *FAST_INPAINT) == 0
    assert calls[-1]["hole"] == "alpha"
    filled = load_image(tmp_path / "filled.png")
    rgba = load_image(hole_files["rgba"])
    expected = real(rgba, rgba[..., 3] < 0.5, neighborhood_sizes=(8,), levels=1, max_iterations=1, rng=0)
    assert filled.shape == (48, 48, 4) and np.abs(filled - expected).max() <= 1 / 255
    assert filled[..., 3].min() > 0.5  # the transparent pixels are filled, and opaque
    assert run("inpaint", hole_files["rgba"], "--hole-channel", "a", "--invert-mask", "-o", str(tmp_path / "i.png"),
               *FAST_INPAINT) == 0
    assert np.array_equal(calls[-1]["hole"], ~hole_files["hole"])
    capsys.readouterr()  # (that hole covers 88 %: a warning)
    for argv, words in ((["--hole-channel", "a"], "--hole-channel a takes the hole from the input's alpha channel"),
                        ([], "the hole is missing: pass --hole FILE"),
                        (["--hole-channel", "a", "--hole", hole_files["white"]], "not both")):
        source = hole_files["image"] if argv[:1] != ["--hole-channel"] or "--hole" not in argv else hole_files["rgba"]
        assert words in _one_line_error(capsys, run("inpaint", source, "-o", str(tmp_path / "e.png"), *argv))
