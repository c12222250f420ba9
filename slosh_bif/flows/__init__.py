"""The flows of the two full models, below the wings that use them: the compiled DOP853
integrator of the smooth model (9) and its variational equations (numba around the generated
kernels, scipy's DOP853 the fallback), band-limited noise (47), and the exact flow of the
vibro-impact model (8) between and across impacts (propagators, saltation matrices). Simulations,
shooting and the orbits of (8) all integrate through here."""

from slosh_bif.flows.integrator import HAVE_NUMBA, integrate, integrate_grid

__all__ = ["HAVE_NUMBA", "integrate", "integrate_grid"]
