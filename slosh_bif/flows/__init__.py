"""The flows of the two full models, below the wings that use them: one folder a model
(:mod:`~slosh_bif.flows.smooth`: the compiled DOP853 integrator of (9) and its variational
equations, scipy's DOP853 the fallback; :mod:`~slosh_bif.flows.impact`: the exact flow of (8)
between and across impacts) and what both use beside them (numba's presence, the band-limited
noise of (47), the periodic QR of the Floquet multipliers, the compiled loops, loaded at the
first integration). Simulations, shooting and the orbits of (8) all integrate through here."""

import importlib

__all__ = ["HAVE_NUMBA", "integrate", "integrate_grid"]


def __getattr__(name):
    # loaded on first use: the impact model's flow does not need the DOP853 integrator's module
    if name in __all__:
        value = getattr(importlib.import_module("slosh_bif.flows.smooth.integrator"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'slosh_bif.flows' has no attribute {name!r}")
