"""The generated code is what the derivation writes today (byte for byte)."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_generated_code_is_fresh():
    result = subprocess.run([sys.executable, "-m", "slosh_bif.cli", "derive", "--check"], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stderr


def test_check_fails_on_stale_code(tmp_path):
    (tmp_path / "models.py").write_text("# stale\n")
    script = ROOT / "derivations" / "generate.py"
    result = subprocess.run([sys.executable, str(script), "--check", "--out", str(tmp_path)], capture_output=True, text=True)
    assert result.returncode == 1 and "stale generated code" in result.stderr


def test_regeneration_is_byte_identical(tmp_path):
    script = ROOT / "derivations" / "generate.py"
    subprocess.run([sys.executable, str(script), "--out", str(tmp_path)], check=True, capture_output=True)
    for path in (ROOT / "slosh_bif" / "_generated").glob("*.py"):
        assert (tmp_path / path.name).read_bytes() == path.read_bytes(), path.name
