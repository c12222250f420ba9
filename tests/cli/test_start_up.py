"""Start-up without an ahead-of-time compiler (slosh_bif.flows.loops): a command loads numba only
when it integrates, no command leaves a process behind, and ``slosh-bif compile`` fills numba's
cache (and the package's bytecode) so that a later command compiles nothing."""

import os
import subprocess
import sys
import uuid
from pathlib import Path

import pytest

# the n = 6 symmetric orbit at sigma = -6 (the speed benchmark's case), over a short range
GUESS = "0.63296198077934629,0.20595836024122491,-0.50665000005633232,-1.1117831464853676"
SHORT_SHOOT = ["shoot", "--preset", "fig10", "--set", "n=6", "--set", "sigma=-6", "--guess", GUESS]
SHORT_SHOOT += ["--no-switch", "--sigma-min", "-6", "--sigma-max", "-5", "-q"]

# run a command as the console script does, then say whether numba was imported
_RUN = (
    "import sys\n"
    "import slosh_bif.cli as cli\n"
    "status = cli.main(sys.argv[1:])\n"
    "print('numba loaded:', 'numba' in sys.modules, file=sys.stderr)\n"
    "sys.exit(status)\n"
)


def _run(arguments, env=None):
    run = subprocess.run(
        [sys.executable, "-c", _RUN, *arguments],
        capture_output=True,
        text=True,
        env={**os.environ, **(env or {})},
        timeout=600,
    )
    assert run.returncode == 0, run.stderr[-800:]
    return run.stderr


def _processes_with(marker: str) -> list:
    """The live processes whose environment carries ``marker`` (inherited by every child)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and entry.name != str(os.getpid()):
            try:
                if marker.encode() in (entry / "environ").read_bytes():
                    found.append(entry.name)
            except OSError:  # gone, or not ours to read
                pass
    return found


def test_the_shooting_modules_import_without_numba_and_a_command_that_does_not_integrate_never_loads_it(
    tmp_path,
):
    # (`info` is checked without any heavy library in tests/test_architecture.py)
    code = (
        "import sys, slosh_bif.orbits.shooting, slosh_bif.orbits.floquet, slosh_bif.cli as cli\n"
        + _RUN[_RUN.index("status") :]
    )
    run = subprocess.run(
        [sys.executable, "-c", code, "frc", "--preset", "fig10", "-q", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stderr[-800:]
    assert "numba loaded: False" in run.stderr


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="reads live processes from /proc")
def test_a_shooting_run_loads_numba_and_leaves_no_process_behind(tmp_path):
    marker = f"SLOSH_BIF_TEST_RUN={uuid.uuid4().hex}"
    name, value = marker.split("=")
    script = Path(sys.executable).with_name("slosh-bif")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "slosh_bif"]
    run = subprocess.run(
        [*command, *SHORT_SHOOT, "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        env={**os.environ, name: value},
        timeout=600,
    )
    assert run.returncode == 0, run.stderr[-800:]
    assert (tmp_path / "branch.csv").is_file()
    assert _processes_with(marker) == []  # the figure's process and everything else have ended
    assert "numba loaded: True" in _run([*SHORT_SHOOT, "--out", str(tmp_path / "again")])


@pytest.mark.slow
def test_compile_fills_numbas_cache_so_that_a_later_command_compiles_nothing(tmp_path):
    cache = tmp_path / "cache"
    _run(["compile"], env={"NUMBA_CACHE_DIR": str(cache)})
    indexes = {path: path.stat().st_mtime_ns for path in cache.rglob("*.nbi")}
    names = " ".join(str(path.relative_to(cache)) for path in indexes)
    loops = (
        "_dop853_loop",
        "_grid_loop",
        "_arcs_loop",
        "_replay_loop",
        "periodic_qr.periodic_qr",
        "flow._run",
    )
    for loop in loops:
        assert loop in names, loop
    import importlib.util

    import slosh_bif.orbits.shooting as module  # and the bytecode a command would otherwise compile

    assert Path(importlib.util.cache_from_source(module.__file__)).is_file()
    _run([*SHORT_SHOOT, "--out", str(tmp_path / "out")], env={"NUMBA_CACHE_DIR": str(cache)})
    for path, mtime in indexes.items():  # an index is rewritten when its function compiles again
        assert path.stat().st_mtime_ns == mtime, path.name
    assert {path for path in cache.rglob("*.nbi")} == set(indexes)  # and nothing new compiled


# a stand-in for a process pool's manager thread deadlocked on a killed worker, holding the exit
HELD_EXIT = """
import threading
import slosh_bif.cli as cli
import slosh_bif.cli.exits as exits
exits.EXIT_WAIT = 1.0
def main(argv=None):
    threading.Thread(target=threading.Event().wait).start()
    return 3
cli.main = main
cli.run()
"""
# SIGTERM, then a stop path that hangs (a pool's shutdown waiting on a lock, say)
HELD_STOP = """
import os, signal, threading, time
from slosh_bif.cli.exits import stop_signals
with stop_signals(wait=1.0):
    try:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(60)
    except KeyboardInterrupt:
        threading.Event().wait()
"""


@pytest.mark.parametrize("code, status, after", [(HELD_EXIT, 3, "exit"), (HELD_STOP, 143, "stop")])
def test_an_exit_or_a_stop_held_by_a_thread_that_never_ends_is_bounded(code, status, after):
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == status, run.stderr[-800:]
    assert f"the {after} waited 1 s for a thread or child process; leaving without it" in run.stderr
