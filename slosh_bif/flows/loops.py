"""The compiled loops, loaded on first use: the three DOP853 loops of
:mod:`slosh_bif.flows.smooth.dop853` and the replay of :mod:`slosh_bif.flows.smooth.tape` (with the
generated kernels of (9), its variational equations and the random forcing of (47) inlined) and
the periodic QR sweep of :mod:`slosh_bif.flows.periodic_qr` (the Floquet multipliers' periodic
Schur decomposition).

Why lazily: importing numba costs 0.1-0.3 s and its first call, even with numba's on-disk cache
warm, another 0.2-0.3 s (it builds its target context, which imports scipy.linalg). A command that
never integrates (``info``, ``frc``, ``critical``, ``tank``) then never pays it, and one that does
pays it at its first integration. numba's cache (``cache=True`` on every loop,
:mod:`slosh_bif.flows.compiled`) keeps the machine code between processes; ``slosh-bif compile``
fills it ahead of a first run. Nothing runs in the background and no process outlives a command.
"""

from __future__ import annotations

import importlib
import types

__all__ = ["compiled", "ENTRIES"]

ENTRIES = {  # the module of slosh_bif.flows -> its loops
    "smooth.dop853": ("dop853_loop", "grid_loop", "arcs_loop"),
    "smooth.tape": ("replay_loop",),
    "periodic_qr": ("periodic_qr",),
}
_LOADED = []  # the process's loops, loaded once


def compiled():
    """The compiled loops (the names of :data:`ENTRIES`, as attributes), numba's just-in-time
    functions with their on-disk cache; None where numba does not import (the scipy and numpy
    paths run instead)."""
    if not _LOADED:
        from slosh_bif.flows.compiled import HAVE_NUMBA  # imports numba

        modules = {name: importlib.import_module(f"slosh_bif.flows.{name}") for name in ENTRIES}
        _LOADED.append(
            types.SimpleNamespace(
                **{
                    entry: getattr(modules[name], entry)
                    for name, entries in ENTRIES.items()
                    for entry in entries
                }
            )
            if HAVE_NUMBA
            else None
        )
    return _LOADED[0]
