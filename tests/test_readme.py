"""The README's promises: its two commands, its quick start, and .ci/run running the same."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_readme_opens_with_the_install_and_test_commands():
    blocks = re.findall(r"```bash\n(.*?)```", README, re.S)
    assert "pip install . && texsynth demo" in blocks[0]
    assert "pip install -e '.[test]' && python3 -m pytest" in blocks[1]


def test_ci_runs_the_readme_test_command():
    test_command = re.findall(r"```bash\n(.*?)```", README, re.S)[1].strip()
    pip_part, pytest_part = test_command.replace("python3 ", "python ").split(" && ")
    ci = (ROOT / ".ci" / "run").read_text()
    assert pip_part.replace("pip install", "pip install --quiet") in ci
    assert pytest_part in ci


def test_quick_start_runs(tmp_path, monkeypatch):
    code = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README quick start", "exec"), {})
    assert any(tmp_path.iterdir())  # it saved its image
