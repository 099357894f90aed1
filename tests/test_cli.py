"""The texsynth command: list, demo, errors (methods are tested with their modules' CLI tests here too)."""

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
    ramp = cli._ramp((3, 5))
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
    assert run("mix", str(pa), str(pb), "-o", str(out), "--size", "96x32", "--weights", "ramp", "--seed", "0") == 0
    mix = load_image(out)
    assert mix.shape == (32, 96, 3)
    left, right = mix[:, :24], mix[:, -24:]
    # each end is made of its own source: nearer (in patch energy) to it than to the other source
    assert texture_energy(left, a) < texture_energy(left, b)
    assert texture_energy(right, b) < texture_energy(right, a)


def test_pixels_and_solid_commands(tmp_path):
    src = save_image(tmp_path / "wood.png", data.load("wood")[:24, :24])
    assert run("pixels", str(src), "-o", str(tmp_path / "p.png"), "--size", "40x32", "--seed", "0") == 0
    assert load_image(tmp_path / "p.png").shape == (32, 40, 3)
    assert run("solid", str(src), "-o", str(tmp_path / "s.png"), "--size", "20", "--seed", "0") == 0
    volume = np.load(tmp_path / "s.npy")
    assert volume.shape == (20, 20, 20, 3)  # one number: a cube
    for axis in "zyx":
        assert load_image(tmp_path / f"s_slice_{axis}.png").shape == (20, 20, 3)
