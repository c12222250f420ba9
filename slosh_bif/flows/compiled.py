"""numba, optional at run time: ``jit`` compiles with an on-disk cache when numba imports and
returns the plain Python function otherwise (the scipy paths then run instead of the compiled ones).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

try:  # a core dependency; the scipy path covers a machine where it fails to import
    import numba
except ImportError:  # pragma: no cover - exercised on machines without numba
    numba = None

__all__ = ["HAVE_NUMBA", "forget_stale_compilations", "jit", "numba"]

HAVE_NUMBA = numba is not None


def jit(function=None, inline=False):
    """numba.njit with an on-disk cache when numba is there; the plain function otherwise.
    ``inline``: compiled into each caller (a call between separately compiled functions costs as
    much as a small right-hand side, 25 ns)."""
    # error_model="numpy": a division by zero gives inf/NaN (which the callers test) instead of raising.
    # nogil: a worker's watch on its parent (slosh_bif.simulation.sweep) runs during a long call.
    if function is None:
        return lambda f: jit(f, inline)
    options = {
        "cache": True,
        "nogil": True,
        "error_model": "numpy",
        "inline": "always" if inline else "never",
    }
    return numba.njit(**options)(function) if HAVE_NUMBA else function


def forget_stale_compilations(compiled, modules, stems, name: str) -> None:
    """Remove the cached machine code of the modules ``stems`` (file names without ``.py``, in the
    folder of ``compiled``'s cache) when the sources of ``modules`` have changed since it was
    compiled: numba keys a cache on the contents of a function's own file only, so a loop that
    inlines or calls functions of other files (generated kernels, the impact search) would run
    their stale code. A digest of the sources is kept beside the cache as ``name.sha256``."""
    try:
        folder = Path(compiled._cache._impl.locator.get_cache_path())
    except AttributeError:  # a numba without these internals: nothing to do
        return
    digest = hashlib.sha256(b"".join(Path(m.__file__).read_bytes() for m in modules)).hexdigest()
    marker = folder / f"{name}.sha256"
    try:
        if marker.read_text() == digest:
            return
    except OSError:
        pass
    try:
        for stem in stems:
            for path in folder.glob(f"{stem}.*.nb[ic]"):
                path.unlink(missing_ok=True)
        folder.mkdir(parents=True, exist_ok=True)
        marker.write_text(digest)
    except OSError:  # a read-only cache: numba then keeps its own rule
        pass
