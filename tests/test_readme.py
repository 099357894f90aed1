"""The README's promises: its two commands, its quick start, and .ci/run running the same."""

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_readme_opens_with_the_install_and_test_commands():
    blocks = re.findall(r"```bash\n(.*?)```", README, re.S)
    assert README.index("```bash") < README.index("## ")  # the two commands come first
    assert "python3 -m venv .venv" in blocks[0] and blocks[0].strip().endswith("pip install . && texsynth demo")
    assert "pip install -e '.[test]'" in blocks[1] and "python -m pytest" in blocks[1]


def test_ci_runs_exactly_the_readme_test_command():
    expected = re.findall(r"```bash\n(.*?)```", README, re.S)[1].strip()
    script = ROOT / ".ci" / "run"
    awk = re.search(r"command=\$\(awk '(.*?)' README.md\)", script.read_text()).group(1)
    got = subprocess.run(["awk", awk, str(ROOT / "README.md")], capture_output=True, text=True, check=True)
    assert got.stdout.strip() == expected


def test_quick_start_runs(tmp_path, monkeypatch):
    code = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README quick start", "exec"), {})
    assert any(tmp_path.iterdir())  # it saved its image


def test_readme_images_exist_and_stay_small():
    images = re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", README)
    # the first screen: a picture of what the quick start makes, before the recipes
    assert images[0] == "docs/_static/readme_hero.png" and README.index(images[0]) < README.index("## ")
    assert "docs/_static/gallery_strip.png" in images  # every method, under "All the methods"
    for image in images:
        path = ROOT / image
        assert path.is_file(), f"README shows {image}, which does not exist"
        assert path.stat().st_size < 600_000, f"{image} is {path.stat().st_size // 1000} kB; keep README pictures small"
    recipes = [ROOT / image for image in images if "/readme_" in image]
    assert len(recipes) >= 9 and sum(p.stat().st_size for p in recipes) < 800_000  # benchmarks/figure_readme.py


def _recipes():
    """The README's recipes: (title, Python block, command lines)."""
    start = README.index("\n## Recipes")
    part = README[start:README.index("\n## ", start + 5)]
    out = []
    for section in part.split("\n### ")[1:]:
        title = section.splitlines()[0]
        python = re.findall(r"```python\n(.*?)```", section, re.S)
        commands = [line.split("#")[0].strip() for block in re.findall(r"```bash\n(.*?)```", section, re.S)
                    for line in block.splitlines() if line.startswith("texsynth ")]
        out.append((title, python, commands))
    return out


def test_every_recipe_has_a_picture_three_to_six_lines_of_python_and_a_command():
    recipes = _recipes()
    assert len(recipes) >= 8
    for title, python, commands in recipes:
        assert len(python) == 1, title
        lines = [line for line in python[0].splitlines() if line.strip()]
        assert 3 <= len([line for line in lines if not line.startswith(("import ", "from "))]) <= 6, title
        assert commands, f"recipe {title!r} has no command line"


def test_the_recipes_commands_parse():
    # each command line names a command and flags the parser knows (nothing runs)
    import shlex

    from texsynth import cli

    parser = cli.build_parser()
    for title, _, commands in _recipes():
        for command in commands:
            try:
                parser.parse_args(shlex.split(command)[1:])
            except SystemExit:
                raise AssertionError(f"recipe {title!r}: {command!r} does not parse") from None


def test_install_lines_name_extras_that_exist():
    # from a checkout: pip install '.[extra]' (texsynth is not on PyPI)
    import tomllib

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    docs = [README] + [p.read_text() for p in (ROOT / "docs").rglob("*.md") if "_build" not in p.parts]
    docs.append((ROOT / "docs" / "api.rst").read_text())
    # and every message, docstring, example and the notebook a user reads
    docs += [p.read_text() for p in (ROOT / "src" / "texsynth").rglob("*.py")]
    docs += [p.read_text() for p in (ROOT / "examples").iterdir() if p.suffix in (".py", ".txt", ".ipynb")]
    for text in docs:
        assert not re.search(r"pip install ['\"]?texsynth\b", text)
        for extra in re.findall(r"pip install (?:-e )?'?\.\[([a-z,]+)\]", text):
            assert set(extra.split(",")) <= set(extras), extra


@pytest.mark.slow
@pytest.mark.parametrize("recipe", [r[0] for r in _recipes()])
def test_every_recipe_runs_as_written(recipe, tmp_path, monkeypatch):
    code = next(python[0] for title, python, _ in _recipes() if title == recipe)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"README recipe {recipe!r}", "exec"), {})


def test_an_extras_install_hint_works_as_written(monkeypatch):
    from importlib import metadata

    from texsynth.core._extras import install_hint

    # installed: the extra's packages by name, from texsynth's metadata (texsynth itself is not on PyPI)
    assert install_hint("video") == "python -m pip install 'imageio-ffmpeg' (texsynth's video extra)"

    def absent(name):
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(metadata, "requires", absent)  # run from a source tree, uninstalled
    assert install_hint("exr") == "python -m pip install '.[exr]' in a texsynth checkout"
