"""The integration question: the state of (9) after one forcing period at n = 50 and n = 6 by
every integrator the package offers and scipy's ``solve_ivp`` methods, against a compiled
DOP853 run at rtol 1e-13.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.timing import PERIOD, timed
from slosh_bif.flows.smooth import integrator
from slosh_bif.model.equations import SmoothModel
from slosh_bif.model.presets import get_preset

# --- the integration question --------------------------------------------------------------------

INTEGRATION_SETS = ("fig10", "fig12")  # n = 50 and n = 6
IMPLICIT_LOOSEST = 1e-9  # Radau/BDF: seconds per period below this rtol and no better than DOP853


def _integrators(params, y0, tau):
    model = SmoothModel(params)

    def compiled(backend):
        def run(rtol):
            r = integrator.integrate(params, y0, (0.0, tau), rtol=rtol, atol=rtol * 1e-2, backend=backend)
            return r.z, r.nfev

        return run

    def scipy_method(method, jac=None):
        def run(rtol):
            sol = solve_ivp(
                model.rhs,
                (0.0, tau),
                y0,
                method=method,
                rtol=rtol,
                atol=rtol * 1e-2,
                **({"jac": jac} if jac else {}),
            )
            return sol.y[:, -1], sol.nfev

        return run

    return {
        "slosh_bif DOP853 (numba, default)": compiled("numba"),
        "slosh_bif DOP853 (scipy fallback)": compiled("scipy"),
        "scipy DOP853": scipy_method("DOP853"),
        "scipy RK45": scipy_method("RK45"),
        "scipy LSODA": scipy_method("LSODA"),
        "scipy Radau (FD Jacobian)": scipy_method("Radau"),
        "scipy Radau (analytic Jacobian)": scipy_method("Radau", model.jac),
        "scipy BDF (analytic Jacobian)": scipy_method("BDF", model.jac),
    }


def integration_bench(*, quick: bool = False, repeats: int = 3, progress=None):
    """Rows ``(preset, n, method, rtol, seconds, nfev, error)``: one forcing period of (9)."""
    say = progress or (lambda message: None)
    if not integrator.HAVE_NUMBA:
        raise RuntimeError(
            "the integration benchmark compares the compiled integrator: install the 'fast' extra (numba)"
        )
    rtols = (1e-6, 1e-9) if quick else (1e-5, 1e-7, 1e-9, 1e-11)
    rows = []
    for preset in INTEGRATION_SETS:
        pre = get_preset(preset)
        params, y0 = pre.params, pre.state0
        ref = integrator.integrate(params, y0, (0.0, PERIOD), rtol=1e-13, atol=1e-15).z
        for name, run in _integrators(params, y0, PERIOD).items():
            for rtol in rtols:
                if ("Radau" in name or "BDF" in name) and rtol < IMPLICIT_LOOSEST:
                    continue
                say(f"integration, {preset} (n = {params.n}): {name}, rtol {rtol:.0e}")
                with np.errstate(
                    over="ignore", invalid="ignore"
                ):  # trial steps deep in the wall overflow; the error control rejects them
                    run(rtol)  # compile or load the kernels, warm caches: not part of the timing
                    seconds, (z, nfev), runs = timed(lambda: run(rtol), repeats=repeats)
                rows.append(
                    dict(
                        preset=preset,
                        n=params.n,
                        method=name,
                        rtol=rtol,
                        seconds=seconds,
                        runs=runs,
                        nfev=int(nfev),
                        error=float(np.max(np.abs(z - ref))),
                    )
                )
    return rows
