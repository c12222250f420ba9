"""The tutorial's code runs as written (docs/tutorial.md), in order, in one namespace."""

import re
from pathlib import Path

TUTORIAL = Path(__file__).resolve().parents[1] / "docs" / "tutorial.md"


def test_tutorial_code_runs(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", TUTORIAL.read_text(), flags=re.S)
    assert len(blocks) >= 4
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for k, block in enumerate(blocks):
        exec(compile(block, f"{TUTORIAL.name}, block {k + 1}", "exec"), namespace)
    out = capsys.readouterr().out
    assert "peak A =" in out and "symmetric" in out and "stable slow-flow states" in out
    assert (tmp_path / "tutorial-results" / "compare.png").stat().st_size > 10_000
