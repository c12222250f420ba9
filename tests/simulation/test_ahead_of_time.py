"""The compiled loops built ahead of time (slosh_bif.flows.ahead_of_time): bitwise the results of
numba's just-in-time loops on every kernel and of the periodic QR, a run of (9) that imports no
numba, and the rules that keep a stale, broken or unwanted module from loading."""

import os
import subprocess
import sys

import numpy as np
import pytest

from slosh_bif.flows import ahead_of_time
from slosh_bif.flows.noise import band_limited_noise
from slosh_bif.flows.smooth.dop853_interface import TABLEAU, WHICH
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA, kernel_parameters
from slosh_bif.model.presets import get_preset

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled loops need numba")


@pytest.fixture(scope="module")
def built():
    """The module for this source, built here when it is not (about 15-30 s, once a machine)."""
    module = ahead_of_time.load()
    if module is None:
        ahead_of_time.build()
        module = ahead_of_time.load()
    assert module is not None
    return module


def _cases():
    params = get_preset("fig10").params.replace(sigma=3.0)
    noise = band_limited_noise(0.3, seed=4, duration=2 * np.pi)
    y = np.array([0.6, 0.2, -0.5, -1.1])
    shooting = np.concatenate([y, np.eye(4).ravel(), np.zeros(9)])
    pair = kernel_parameters(params, sensitivities=("gamma", "lam"))
    return [
        ("plain", y, kernel_parameters(params)),
        ("noisy", y, kernel_parameters(params, noise=noise)),
        ("shooting", shooting, kernel_parameters(params)),
        ("pair", shooting, pair),
    ]


@pytest.mark.parametrize("n", [6, 50])
def test_the_module_built_ahead_of_time_gives_numbas_results_bitwise(built, n):
    from slosh_bif.flows.smooth import dop853  # the just-in-time loops, from the same source

    for which, z0, pars in _cases():
        pars = pars.copy()
        pars[7] = n
        k = WHICH[which]
        one = (k, 0.0, 2 * np.pi, z0, pars, 1e-10, 1e-12, 0.0, 2_000_000, *TABLEAU)
        ours, theirs = built.dop853_loop(*one), dop853.dop853_loop(*one)
        assert ours[5] == 0 and ours[1:] == theirs[1:], which
        np.testing.assert_array_equal(ours[0], theirs[0])
        taus = np.linspace(0.0, 2 * np.pi, 5)
        if which in ("plain", "noisy"):
            grid = (k, taus, z0, pars, 1e-10, 1e-12, 2_000_000, *TABLEAU)
            ours, theirs = built.grid_loop(*grid), dop853.grid_loop(*grid)
        else:
            starts = np.ascontiguousarray(np.array([z0[:4], -z0[:4], 0.5 * z0[:4], z0[:4]]))
            arcs = (k, taus, starts, pars, 1e-10, 1e-12, 2_000_000, *TABLEAU)
            ours, theirs = built.arcs_loop(*arcs), dop853.arcs_loop(*arcs)
        assert ours[1:] == theirs[1:], which
        np.testing.assert_array_equal(ours[0], theirs[0])


def test_the_periodic_qr_built_ahead_of_time_is_numbas_bitwise(built):
    from slosh_bif.flows import periodic_qr

    rng = np.random.default_rng(7)
    for m, n in ((4, 4), (16, 4), (3, 8)):
        mats = np.ascontiguousarray(np.diag(np.logspace(2, -6, n)) @ rng.normal(size=(m, n, n)))
        q0 = np.ascontiguousarray(np.linalg.qr(rng.normal(size=(n, n)))[0])
        ours, theirs = built.periodic_qr(mats, q0, 50, 1e-14), periodic_qr.periodic_qr(mats, q0, 50, 1e-14)
        assert ours[3:] == theirs[3:]
        for a, b in zip(ours[:3], theirs[:3]):
            np.testing.assert_array_equal(a, b)


def test_a_shooting_run_with_the_built_module_imports_no_numba_and_writes_the_same_files(built, tmp_path):
    # The n = 6 branch over a short range, run by the command line as a user runs it, once on the
    # module built ahead of time and once with it turned off (numba's just-in-time loops).
    code = (
        "import sys\n"
        "from slosh_bif.cli import main\n"
        "status = main(sys.argv[1:])\n"
        "print('numba loaded:', 'numba' in sys.modules, file=sys.stderr)\n"
        "sys.exit(status)\n"
    )
    guess = "0.63296198077934629,0.20595836024122491,-0.50665000005633232,-1.1117831464853676"
    command = ["shoot", "--preset", "fig10", "--set", "n=6", "--set", "sigma=-6", "--guess", guess]
    command += ["--no-switch", "--sigma-min", "-6", "--sigma-max", "-4"]
    runs = {}
    for label, switch in (("ahead", "1"), ("jit", "0")):
        env = {**os.environ, ahead_of_time.DISABLE: switch}
        out = tmp_path / label
        run = subprocess.run(
            [sys.executable, "-c", code, *command, "--out", str(out)],
            capture_output=True,
            text=True,
            env=env,
            timeout=600,
        )
        assert run.returncode == 0, run.stderr[-500:]
        runs[label] = (run.stderr, out)
    assert "numba loaded: False" in runs["ahead"][0]
    assert "numba loaded: True" in runs["jit"][0]
    names = sorted(p.name for p in runs["ahead"][1].iterdir())
    assert names == sorted(p.name for p in runs["jit"][1].iterdir()) and names
    for name in names:
        assert (runs["ahead"][1] / name).read_bytes() == (runs["jit"][1] / name).read_bytes(), name


def test_the_digest_follows_every_source(tmp_path):
    sources = []
    for name in ("loop.py", "kernels.py"):
        sources.append(tmp_path / name)
        sources[-1].write_text(f"# {name}\n")
    first = ahead_of_time.digest(tuple(sources))
    assert ahead_of_time.digest(tuple(sources)) == first
    sources[1].write_text("# kernels.py, regenerated\n")
    assert ahead_of_time.digest(tuple(sources)) != first


def test_a_missing_broken_or_unwanted_module_is_not_loaded(tmp_path, monkeypatch):
    path = tmp_path / "slosh_bif_ahead_0123.cpython-311-x86_64-linux-gnu.so"
    assert ahead_of_time.load(path) is None  # not built
    path.write_bytes(b"not a shared object")
    assert ahead_of_time.load(path) is None  # broken: the just-in-time path runs
    monkeypatch.setenv(ahead_of_time.DISABLE, "0")
    assert ahead_of_time.disabled() and ahead_of_time.load(ahead_of_time.module_path()) is None
    assert not ahead_of_time.build_in_background()


def test_a_background_build_starts_once_and_not_where_it_failed(tmp_path, monkeypatch):
    started = []
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv(ahead_of_time.DISABLE, raising=False)
    monkeypatch.setattr(ahead_of_time.subprocess, "Popen", lambda *a, **k: started.append(a[0]))
    path = ahead_of_time.module_path()
    assert path.parent == tmp_path / "slosh_bif"
    assert ahead_of_time.build_in_background() and len(started) == 1
    assert started[0][-1] == str(path)
    assert not ahead_of_time.build_in_background() and len(started) == 1  # its lock: being built
    path.with_name(path.name + ".building").unlink()
    path.with_name(path.name + ".failed").write_text("no C compiler")
    assert ahead_of_time.failure(path) == "no C compiler"
    assert not ahead_of_time.build_in_background() and len(started) == 1  # known to fail here


def test_compile_refuses_while_turned_off(monkeypatch, capsys):
    from slosh_bif.cli import main

    monkeypatch.setenv(ahead_of_time.DISABLE, "off")
    assert main(["compile"]) == 2
    assert ahead_of_time.DISABLE in capsys.readouterr().err


def test_compile_says_where_the_built_module_is(built, capsys):
    from slosh_bif.cli import main

    assert main(["compile"]) == 0
    assert str(ahead_of_time.module_path()) in capsys.readouterr().out
