"""The console entry leaves without the interpreter's teardown: what it wrote must be complete,
its output flushed through a pipe, and its exit status the command's."""

import csv
import subprocess
import sys

import numpy as np


def _run(*arguments):
    return subprocess.run(
        [sys.executable, "-m", "slosh_bif.cli", *arguments], capture_output=True, text=True, timeout=300
    )


def test_files_and_output_are_complete_after_the_fast_exit(tmp_path):
    done = _run("frc", "--preset", "fig10", "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    assert done.stdout.rstrip().endswith("frc.png")  # the last line reached the pipe
    rows = list(csv.DictReader((tmp_path / "frc.csv").open()))
    assert len(rows) > 50 and rows[-1]["sigma"]
    png = (tmp_path / "frc.png").read_bytes()
    assert png.startswith(b"\x89PNG") and png.endswith(b"IEND\xaeB`\x82")  # the PNG's closing chunk
    with np.load(tmp_path / "frc_branch0.npz") as saved:
        assert len(saved["p"]) == len(rows)


def test_the_exit_status_is_the_commands():
    done = _run("info", "--preset", "no-such-preset")
    assert done.returncode == 2 and "error" in done.stderr
    assert _run("info", "--preset", "fig10").returncode == 0
