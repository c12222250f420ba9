"""Time integration of the full smooth model (9) with scipy's ``solve_ivp``.

The generated analytic Jacobian is passed to the implicit methods (Radau, BDF, LSODA); the
explicit ones (DOP853, RK45) ignore it. The wall term ``chi w**(2n+1)`` makes the problem stiff
during impacts at large n, which is where the implicit methods pay off.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.integrate import solve_ivp

from .models import SmoothModel
from .params import Params

__all__ = ["Trajectory", "integrate_smooth"]

_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
_IMPLICIT = ("Radau", "BDF", "LSODA")


@dataclasses.dataclass(frozen=True)
class Trajectory:
    """A solution of the smooth model: times ``t`` (N,), states ``y`` (4, N), and how it ended."""

    t: np.ndarray
    y: np.ndarray
    success: bool
    message: str
    nfev: int


def integrate_smooth(
    params: Params,
    state0,
    t_span,
    *,
    method: str = "DOP853",
    rtol: float = 1e-9,
    atol: float = 1e-11,
    t_eval=None,
    max_step: float = np.inf,
) -> Trajectory:
    """Integrate model (9) from ``state0 = [X, X', w, w']`` over ``t_span``.

    Returns a :class:`Trajectory`; ``success`` is False (with scipy's message) when the
    integrator gave up.
    """
    if method not in _METHODS:
        raise ValueError(f"method must be one of {', '.join(_METHODS)}; got {method!r}")
    for name, value in (("rtol", rtol), ("atol", atol)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be positive and finite; got {value!r}")
    y0 = np.asarray(state0, dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise ValueError(f"state0 must be 4 finite numbers [X, X', w, w']; got {state0!r}")
    model = SmoothModel(params)
    extra = {"jac": model.jac} if method in _IMPLICIT else {}
    with np.errstate(over="ignore", invalid="ignore"):  # trial steps far inside the wall may overflow
        sol = solve_ivp(
            model.rhs, t_span, y0, method=method, rtol=rtol, atol=atol, t_eval=t_eval, max_step=max_step, **extra
        )
    return Trajectory(t=sol.t, y=sol.y, success=bool(sol.success), message=sol.message, nfev=int(sol.nfev))
