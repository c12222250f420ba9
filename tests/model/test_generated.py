"""The generated code and REPORT.md are what the derivation writes today (byte for byte)."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_derive_check_passes_on_the_committed_tree():
    # --check renders everything from the sympy derivation and compares byte for byte.
    result = subprocess.run(
        [sys.executable, "-m", "slosh_bif.cli", "derive", "--check"], capture_output=True, text=True, cwd=ROOT
    )
    assert result.returncode == 0, result.stderr


@pytest.mark.slow  # a second derivation (25 s); the passing check runs by default
def test_check_fails_on_stale_code(tmp_path):
    (tmp_path / "slosh_bif" / "_generated").mkdir(parents=True)
    (tmp_path / "slosh_bif" / "_generated" / "models.py").write_text("# stale\n")
    script = ROOT / "derivations" / "generate.py"
    result = subprocess.run(
        [sys.executable, str(script), "--check", "--out", str(tmp_path)], capture_output=True, text=True
    )
    assert result.returncode == 1 and "stale generated code" in result.stderr
