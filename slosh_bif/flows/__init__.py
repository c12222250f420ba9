"""The flows of the two full models, below the wings that use them: the compiled DOP853
integrator of the smooth model (9) and its variational equations (numba around the generated
kernels, scipy's DOP853 the fallback), band-limited noise (47), and the exact flow of the
vibro-impact model (8) between and across impacts (propagators, saltation matrices). Simulations,
shooting and the orbits of (8) all integrate through here."""

import importlib

__all__ = ["HAVE_NUMBA", "integrate", "integrate_grid"]


def __getattr__(name):
    # loaded on first use: the impact model's flow does not need the DOP853 integrator's module
    if name in __all__:
        value = getattr(importlib.import_module("slosh_bif.flows.integrator"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'slosh_bif.flows' has no attribute {name!r}")
