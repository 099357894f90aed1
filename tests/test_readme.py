"""The README's promises: its two commands, its quick start, and .ci/run running the same."""

import re
import subprocess
from pathlib import Path

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
    assert "docs/_static/gallery_strip.png" in images  # the gallery strip under the two commands
    for image in images:
        path = ROOT / image
        assert path.is_file(), f"README shows {image}, which does not exist"
        assert path.stat().st_size < 600_000, f"{image} is {path.stat().st_size // 1000} kB; keep README pictures small"
