"""The compiled loops built ahead of time: the three DOP853 loops of :mod:`slosh_bif.flows.smooth.dop853`
(with the generated kernels of (9), its variational equations and the random forcing of (47)
inlined) and the periodic QR sweep of :mod:`slosh_bif.flows.periodic_qr` (the Floquet
multipliers' periodic Schur decomposition), compiled by numba's ``pycc`` into an extension module;
:func:`compiled` hands out that module's functions, or numba's just-in-time ones where it is not
built.

Why: loading that module takes about a millisecond, where the just-in-time path first imports
numba (0.2-0.3 s) and, at its first call even with numba's cache warm, builds numba's target
context (0.25-0.45 s; it imports scipy.linalg). A command of (9) that needs nothing else of numba
starts in a fraction of the time. The results are bitwise the same: one source, the same compiler
(a test compares every entry).

The module's name carries a digest of everything compiled into it (this file, the loops and their
interface, the periodic QR, the generated kernels and tableau, the integer power, numba's and
numpy's versions, the interpreter's extension tag, the processor it is compiled for): a change
anywhere gives a new name, so a stale module is never loaded.
It is built once per machine, in 5-30 s: by ``slosh-bif compile``, or in the background at low
priority after a command ran the loops just in time. It lives beside numba's cache
(``$NUMBA_CACHE_DIR/slosh_bif`` when that is set, else ``slosh_bif/flows/__pycache__`` when
writable, else ``~/.cache/slosh_bif``). Building needs setuptools and a C compiler besides numba;
where one is missing, the reason is kept beside the module's path (``slosh-bif compile`` says it)
and the just-in-time path runs, as it does with ``SLOSH_BIF_AHEAD_OF_TIME=0``.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import io
import os
import subprocess
import sys
import tempfile
import time
import types
import warnings
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np

__all__ = ["DISABLE", "compiled", "load", "build", "build_in_background", "module_path", "failure"]

DISABLE = "SLOSH_BIF_AHEAD_OF_TIME"  # "0" (or "off", "no", "false"): neither load nor build the module
_PREFIX = "slosh_bif_ahead_"
_MODULES = ("smooth.dop853", "periodic_qr")  # slosh_bif.flows modules whose AHEAD_OF_TIME entries are built
_STALE_LOCK_SECONDS = 900.0  # a build's lock older than this was left by a build that was killed
_HERE = Path(__file__).resolve().parent
_SOURCES = (
    _HERE / "ahead_of_time.py",
    _HERE / "smooth" / "dop853.py",
    _HERE / "smooth" / "dop853_interface.py",
    _HERE / "periodic_qr.py",
    _HERE / "compiled.py",
    _HERE.parent / "model" / "powers.py",
    _HERE.parent / "model" / "_generated" / "kernels.py",
    _HERE.parent / "model" / "_generated" / "dop853_tableau.py",
)


def disabled() -> bool:
    return os.environ.get(DISABLE, "").strip().lower() in ("0", "off", "no", "false")


def _numba_version_file():
    spec = importlib.util.find_spec("numba")  # located, not imported
    if spec is None or not spec.origin:
        return None
    version = Path(spec.origin).with_name("_version.py")
    return version if version.is_file() else Path(spec.origin)


def _processor() -> str:
    """The processor's model and features (Linux's /proc/cpuinfo, else what platform knows): the
    module is compiled for this processor, so a cache shared with another machine is not loaded
    there."""
    try:
        with open("/proc/cpuinfo") as info:
            return "".join(
                line for line in info.read(65536).splitlines(True)[:30] if "model" in line or "flags" in line
            )
    except OSError:
        import platform

        return f"{platform.machine()} {platform.processor()}"


def digest(sources=_SOURCES) -> str:
    """20 hex digits over the sources compiled into the module, the versions it depends on and
    the processor it is compiled for."""
    numba_version = _numba_version_file()
    h = hashlib.sha256()
    for path in (*sources, *([numba_version] if numba_version else [])):
        h.update(Path(path).read_bytes())
    h.update(f"{np.__version__}|{sys.version}|{importlib.machinery.EXTENSION_SUFFIXES[0]}".encode())
    h.update(_processor().encode())
    return h.hexdigest()[:20]


def cache_dir() -> Path:
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / "slosh_bif"
    inside = _HERE / "__pycache__"
    if os.access(inside if inside.is_dir() else _HERE, os.W_OK):
        return inside
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "slosh_bif"


def module_path() -> Path:
    """Where this source's module is (or would be) built."""
    return cache_dir() / f"{_PREFIX}{digest()}{importlib.machinery.EXTENSION_SUFFIXES[0]}"


def _marker(path: Path, kind: str) -> Path:
    return path.with_name(f"{path.name}.{kind}")


def failure(path=None):
    """Why the last build of this source's module failed here, or None."""
    marker = _marker(Path(path or module_path()), "failed")
    try:
        return marker.read_text().strip() or "unknown reason"
    except OSError:
        return None


ENTRIES = ("dop853_loop", "grid_loop", "arcs_loop", "periodic_qr")


def load(path=None):
    """The built module (its functions :data:`ENTRIES`), or None: not built for this source,
    turned off, or it would not load."""
    if disabled():
        return None
    path = Path(path or module_path())
    if not path.is_file():
        return None
    try:
        spec = importlib.util.spec_from_file_location(path.name.split(".")[0], path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    except (ImportError, OSError):
        return None
    if not all(hasattr(module, name) for name in ENTRIES):
        return None
    return module


_COMPILED = []  # the process's choice, made once


def compiled():
    """The compiled functions (:data:`ENTRIES`, as attributes): the module built ahead of time when
    it is there for this source, else numba's just-in-time functions of the same source; None
    without numba."""
    if not _COMPILED:
        module = load()
        if module is None:
            jit = [importlib.import_module(f"slosh_bif.flows.{name}") for name in _MODULES]
            if jit[0].HAVE_NUMBA:
                module = types.SimpleNamespace(
                    **{entry: getattr(m, entry) for m in jit for entry in m.AHEAD_OF_TIME}
                )
        _COMPILED.append(module)
    return _COMPILED[0]


def build(path=None) -> Path:
    """Compile the entries (:data:`ENTRIES`) into the module at ``path`` (default
    :func:`module_path`), replacing it at once when done; returns the path. Raises RuntimeError
    saying what failed (numba's pycc, setuptools or a C compiler missing, or the compiler's
    error)."""
    path = Path(path or module_path())
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # pycc's pending deprecation
            from numba.pycc import CC
    except ImportError as err:
        raise RuntimeError(f"numba's ahead-of-time compiler (numba.pycc) is not available: {err}") from None
    entries = {}
    for name in _MODULES:
        entries.update(importlib.import_module(f"slosh_bif.flows.{name}").AHEAD_OF_TIME)

    with tempfile.TemporaryDirectory(dir=path.parent, prefix=".building-") as work:
        cc = CC(path.name.split(".")[0])
        cc.output_dir = work
        cc.verbose = False
        cc.target_cpu = "host"  # as numba's just-in-time code; the digest names the processor
        for name, (entry, signature) in entries.items():
            cc.export(name, signature)(entry)
        try:
            with warnings.catch_warnings(), redirect_stdout(io.StringIO()):
                warnings.simplefilter("ignore")
                cc.compile()
        except Exception as err:  # the compiler's or the linker's own error, whatever its type
            raise RuntimeError(
                f"building the loops ahead of time failed: {type(err).__name__}: {err}"
            ) from None
        os.replace(Path(work) / cc.output_file, path)
    _marker(path, "failed").unlink(missing_ok=True)
    for other in path.parent.glob(f"{_PREFIX}*"):  # modules of earlier sources, and their markers
        if not other.name.startswith(path.name):
            other.unlink(missing_ok=True)
    return path


def _take_lock(lock: Path) -> bool:
    for _ in range(2):
        try:
            os.close(os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            return True
        except FileExistsError:
            try:
                if time.time() - lock.stat().st_mtime < _STALE_LOCK_SECONDS:
                    return False  # another process is building it
                lock.unlink()
            except OSError:
                return False
        except OSError:  # a read-only cache: no build
            return False
    return False


def build_in_background() -> bool:
    """Start a detached, low-priority build of the module when it is missing, not turned off, not
    being built by another process and not known to fail here. True if one was started."""
    if disabled() or importlib.util.find_spec("numba") is None:
        return False
    path = module_path()
    if path.exists() or failure(path) is not None:
        return False
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    if not _take_lock(_marker(path, "building")):
        return False
    subprocess.Popen(
        [sys.executable, "-m", "slosh_bif.flows.ahead_of_time", "--background", str(path)],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
        close_fds=True,
    )
    return True


def _background_build(path: Path) -> int:
    """The detached build's process: at low priority; a failure is kept beside the module."""
    try:
        os.nice(10)
    except (AttributeError, OSError):
        pass
    try:
        build(path)
        return 0
    except Exception as err:  # kept for `slosh-bif compile` to say, whatever it was
        try:
            _marker(path, "failed").write_text(str(err))
        except OSError:
            pass
        return 1
    finally:
        _marker(path, "building").unlink(missing_ok=True)


if __name__ == "__main__" and sys.argv[1:2] == ["--background"]:
    sys.exit(_background_build(Path(sys.argv[2])))
