"""``shoot --start scan --resume`` (issue 18): a scan interrupted after some of its families were
traced and resumed writes the same branches as an uninterrupted scan, file for file."""

import os
import signal
import subprocess
import sys
import time

from slosh_bif.cli import main

SCAN = [
    "shoot",
    "--preset",
    "fig13",
    "--set",
    "n=6",
    "--start",
    "scan",
    "--scan-points",
    "3",
    "--scan-random",
    "1",
    "--sigma-min",
    "-6",
    "--sigma-max",
    "8",
]


def test_an_interrupted_scan_resumed_equals_an_uninterrupted_one(tmp_path, capsys):
    first = tmp_path / "a"
    child = subprocess.Popen(
        [sys.executable, "-m", "slosh_bif.cli", *SCAN, "--out", str(first)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(
            signal.SIGINT, signal.SIG_DFL
        ),  # as a terminal's Ctrl-C finds it (see test_signals.default_sigint)
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (first / "scan.pickle").exists() and child.poll() is None:
        time.sleep(0.1)
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=60)
    assert child.returncode == 130, err
    assert (first / "scan.pickle").exists() and not (first / "branch.csv").exists()
    assert main([*SCAN, "--resume", "--out", str(first)]) == 0
    assert "resuming:" in capsys.readouterr().err
    assert main([*SCAN, "--out", str(tmp_path / "b")]) == 0
    for name in ("branch.csv", "families.csv"):
        assert (first / name).read_text() == (tmp_path / "b" / name).read_text(), name
    # other settings, or a start that is not a scan: one line, before any work
    assert main([*SCAN[:-1], "7", "--resume", "--out", str(first)]) == 2
    assert "range differ" in capsys.readouterr().err
    assert main(["shoot", "--preset", "fig13", "--resume", "--out", str(tmp_path / "c")]) == 2
    assert "--resume continues an interrupted --start scan" in capsys.readouterr().err
    assert not os.path.exists(tmp_path / "c" / "branch.csv")
