"""The flow of the smooth model (9): the compiled DOP853 integrator (numba around the generated
kernels of (9) and its variational equations, with the forcing of (47)), what its loops take and
return, and scipy's DOP853 as the tested fallback."""
