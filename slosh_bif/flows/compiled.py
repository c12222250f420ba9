"""numba, optional at run time: ``jit`` compiles with an on-disk cache when numba imports and
returns the plain Python function otherwise (the scipy paths then run instead of the compiled ones).
"""

from __future__ import annotations

try:  # a core dependency; the scipy path covers a machine where it fails to import
    import numba
except ImportError:  # pragma: no cover - exercised on machines without numba
    numba = None

__all__ = ["HAVE_NUMBA", "jit", "numba"]

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
