"""The package's shape: imports flow one way (import-linter), every subpackage states its public
names, modules stay small, and ``import slosh_bif`` computes nothing."""

import importlib
import pkgutil
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import slosh_bif

ROOT = Path(__file__).resolve().parents[1]
SUBPACKAGES = ("model", "continuation", "report", "slowflow", "orbits", "simulation", "studies", "cli")


def test_import_contracts_are_kept():
    # The layers, the engine's independence of the model and the absence of cycles are in
    # pyproject.toml; a broken contract lists the offending import.
    exe = shutil.which("lint-imports") or str(Path(sys.executable).parent / "lint-imports")
    result = subprocess.run([exe, "--no-cache"], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-2000:]
    assert "3 kept, 0 broken" in result.stdout


def test_the_code_passes_ruffs_lint_and_format_check():
    # pyflakes, pycodestyle (lines of at most 110 characters) and import order, as pyproject.toml
    # configures them, and ruff format's layout; a failure names the file and line.
    exe = shutil.which("ruff") or str(Path(sys.executable).parent / "ruff")
    for command in ([exe, "check", "--no-cache", "."], [exe, "format", "--check", "--no-cache", "."]):
        result = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-2000:]


def test_the_contract_can_fail(tmp_path):
    # The same linter on a copy of the package with one import running back up the pipeline.
    copy = tmp_path / "slosh_bif"
    shutil.copytree(ROOT / "slosh_bif", copy, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    wavelet = copy / "simulation" / "wavelet.py"
    wavelet.write_text(wavelet.read_text() + "\nfrom slosh_bif.slowflow import flow  # noqa\n")
    exe = shutil.which("lint-imports") or str(Path(sys.executable).parent / "lint-imports")
    result = subprocess.run(
        [exe, "--no-cache"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={"PYTHONPATH": str(tmp_path), "PATH": ""},
    )
    assert result.returncode != 0
    assert "slosh_bif.simulation.wavelet -> slosh_bif.slowflow.flow" in result.stdout


@pytest.mark.parametrize("name", SUBPACKAGES)
def test_every_subpackage_exports_what_it_lists(name):
    package = importlib.import_module(f"slosh_bif.{name}")
    assert package.__doc__, f"slosh_bif.{name} has no docstring"
    assert hasattr(package, "__all__"), f"slosh_bif.{name} has no __all__"
    for public in package.__all__:
        assert hasattr(package, public), (
            f"slosh_bif.{name}.__all__ names {public!r}, which it does not define"
        )


def test_top_level_api_resolves_every_name():
    for public in slosh_bif.__all__:
        assert getattr(slosh_bif, public) is not None
    assert slosh_bif.get_preset("fig10").params.n == 50


def test_import_computes_nothing_and_loads_no_compiler():
    code = (
        "import sys, slosh_bif; print('numba' in sys.modules, 'matplotlib' in sys.modules, 'sympy' in "
        "sys.modules)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.split() == ["False", "False", "False"]


def test_modules_are_small_and_cite_what_they_implement():
    for info in pkgutil.walk_packages(slosh_bif.__path__, "slosh_bif."):
        if "._generated" in info.name or info.name.endswith("__main__"):
            continue
        module = importlib.import_module(info.name)
        path = Path(module.__file__)
        lines = len(path.read_text().splitlines())
        # formatted by ruff at 110 characters; a module past this has a second job to split off
        assert lines <= 400, f"{info.name} has {lines} lines (split it by role)"
        assert module.__doc__ and module.__doc__.strip(), f"{info.name} has no module docstring"


MAX_PARAMETERS = 10  # a kernel that needs more takes its constants as records


def _parameter_counts():
    """(module, function, count) of every public function and method of the package (the
    generated kernels aside), ``self`` and ``cls`` not counted."""
    import ast

    for path in sorted((ROOT / "slosh_bif").rglob("*.py")):
        if "_generated" in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_"):
                a = node.args
                names = [x.arg for x in (*a.posonlyargs, *a.args, *a.kwonlyargs)]
                count = len(names) + bool(a.vararg) + bool(a.kwarg) - (names[:1] in (["self"], ["cls"]))
                yield path.relative_to(ROOT), node.name, count


def test_no_public_function_takes_more_than_ten_parameters():
    counts = list(_parameter_counts())
    assert any(name == "integrate" and n == 10 for _, name, n in counts)  # the count sees a real one
    over = [f"{path}: {name} ({n})" for path, name, n in counts if n > MAX_PARAMETERS]
    assert not over, "functions with more than ten parameters: " + ", ".join(over)


def test_no_installed_module_touches_the_import_path():
    touched = [
        str(path.relative_to(ROOT))
        for path in (ROOT / "slosh_bif").rglob("*.py")
        if "sys.path" in path.read_text()
    ]
    assert not touched, f"modules that change sys.path: {touched}"


def test_the_cli_starts_without_the_heavy_libraries():
    # Start-up (under 0.5 s) is measured by `python -m benchmarks`; this keeps its cause away:
    # scipy.special and scipy.optimize at module level cost every command ~0.4 s, numba and
    # matplotlib more. `info` must run without any of them.
    code = (
        "import sys\n"
        "from slosh_bif.cli import main\n"
        "assert main(['info', '--preset', 'fig10']) == 0\n"
        "heavy = sorted({m.split('.')[0] for m in sys.modules} & {'scipy', 'numba', 'matplotlib', 'sympy'})\n"
        "print(heavy)\n"
        "sys.exit(1 if heavy else 0)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-300:] + run.stderr[-300:]


def test_shooting_loads_no_scipy_solver_and_no_plotting():
    # The compiled path of a shooting run (start-up target of the speed issue: import to the first
    # Newton step): its integrations and Newton need none of scipy.integrate, scipy.optimize,
    # scipy.interpolate (0.3-0.8 s to import) nor matplotlib; the reference paths import them
    # where they run.
    code = (
        "import sys\n"
        "import numpy as np\n"
        "from slosh_bif.model.presets import get_preset\n"
        "from slosh_bif.continuation.corrector import newton_solve\n"
        "from slosh_bif.orbits.shooting import ShootingProblem\n"
        "P = get_preset('fig10').params.replace(sigma=3.0)\n"
        "problem = ShootingProblem(P, symmetric=True, segments=2)\n"
        "x = problem.initial_states([-0.805, 0.099, 0.532, 1.0])\n"
        "newton_solve(problem, x, 3.0, max_iter=2)\n"
        "heavy = [m for m in ('scipy.integrate', 'scipy.optimize', 'scipy.interpolate', 'matplotlib')"
        " if m in sys.modules]\n"
        "print(heavy)\n"
        "sys.exit(1 if heavy else 0)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-300:] + run.stderr[-300:]
