"""The figure drawn by a forked process (report.plot_process): the call runs in the child, its
value and its exception come back as its own, a child without a call is reaped, a call that
cannot be sent or answered is made in the process, no fork where threads run, and ``shoot``'s
figure is the same bytes as one drawn in the process."""

import subprocess
import sys
import textwrap

from slosh_bif.cli import main

SHOOT = ["shoot", "--preset", "fig10", "--no-switch", "--sigma-min", "2", "--sigma-max", "3", "-q"]


def _python(code):
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


def test_the_call_runs_in_the_child_and_its_value_and_exception_come_back():
    out = _python(
        """
        import math, os, threading
        from slosh_bif.report.plot_process import PlotProcess
        with PlotProcess() as plots:
            plots.submit(os.getpid)
            print(plots.result() != os.getpid())
        with PlotProcess() as plots:
            plots.submit(math.sqrt, -1.0)
            try:
                plots.result()
            except ValueError as err:
                print(type(err).__name__)
        with PlotProcess():
            pass  # no call: the child ends
        try:
            os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            print("reaped")
        with PlotProcess() as plots:  # a call that does not pickle is made here
            plots.submit(lambda: os.getpid())
            print(plots.result() == os.getpid())
        import signal, time
        with PlotProcess() as plots:  # a child killed before its answer: the call is made here
            plots.submit(time.sleep, 1.0)
            os.kill(plots._pid, signal.SIGKILL)
            print(plots.result() is None)
        threading.Thread(target=threading.Event().wait, args=(5,), daemon=True).start()
        with PlotProcess() as plots:  # a thread runs: no fork
            plots.submit(os.getpid)
            print(plots.result() == os.getpid())
        """
    )
    assert out == ["True", "ValueError", "reaped", "True", "True", "True"]


def test_shoots_figure_from_the_child_is_the_one_drawn_in_process(tmp_path):
    child = subprocess.run(
        [sys.executable, "-m", "slosh_bif.cli", *SHOOT, "--out", str(tmp_path / "child")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert child.returncode == 0, child.stderr
    # in process, under pytest's worker threads (or forked too where there are none)
    assert main([*SHOOT, "--out", str(tmp_path / "here")]) == 0
    for name in ("branch.png", "branch.csv"):
        assert (tmp_path / "child" / name).read_bytes() == (tmp_path / "here" / name).read_bytes()
