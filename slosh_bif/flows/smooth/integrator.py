"""Integration of the smooth model (9): DOP853 in a numba hot loop (:mod:`slosh_bif.flows.smooth.dop853`),
scipy as the fallback.

Both backends run the same method (DOP853 with scipy's error norm, step-size control and initial
step; the Butcher coefficients read from scipy) on the same generated kernels, and differ only in
rounding and in where output points fall: (9) alone, (9) with its variational equations, two
parameter sensitivities and the Liouville integral for shooting, and (9) with the random forcing of
(47).

Why: one period of (9) at n = 50 takes thousands of steps (the wall term chi w^101 is stiff in an
explicit method's eyes), and a Python right-hand side called from scipy's stepper spends tens of
microseconds a step in interpreter overhead. The compiled loop spends about a microsecond.

``backend="auto"`` takes the compiled loops (numba, a core dependency, imported at the first
integration: :mod:`slosh_bif.flows.loops`) and scipy without numba; ``"numba"`` and ``"scipy"``
force one. Both return the same :class:`Integration` record.
"""

from __future__ import annotations

import math
import typing

import numpy as np

from slosh_bif.flows.loops import compiled
from slosh_bif.flows.noise import BandLimitedNoise
from slosh_bif.flows.smooth.dop853_interface import (
    MESSAGES,
    OK,
    SHOOTING_SIZE,
    TABLEAU,
    WHICH,
    variation_parameters,
    variations_size,
)
from slosh_bif.model.params import REAL_FIELDS, Params, real_pair

__all__ = [
    "HAVE_NUMBA",  # noqa: F822 - module __getattr__: it loads the compiled loops
    "Integration",
    "integrate",
    "integrate_grid",
    "SHOOTING_SIZE",
    "resolve_backend",
    "DEFAULT_SENSITIVITIES",
    "kernel_parameters",
    "integrate_variations",
    "scipy_rhs",
]

DEFAULT_SENSITIVITIES = ("sigma", "Abar")  # the dedicated kernel's pair; any other pair takes the pair kernel


class Integration(typing.NamedTuple):
    """End state of one integration and what it cost (a named tuple, not a frozen dataclass: it is
    made once a call, and the dataclass's constructor cost 2 us, a tenth of a period of (9) at n = 6).

    z : end state (4 for the plain model, 29 with ``shooting=True``)
    steps, rejected, nfev : accepted and rejected steps, right-hand-side evaluations
    h_next : the step size the controller proposes next (warm start for the next call)
    success, message : whether tau1 was reached, and otherwise why not
    """

    z: np.ndarray
    steps: int
    rejected: int
    nfev: int
    h_next: float
    success: bool
    message: str


def __getattr__(name):
    # HAVE_NUMBA, asked for, loads the compiled loops; the integrator itself loads them at its
    # first integration (a command that never integrates never imports numba)
    if name == "HAVE_NUMBA":
        return compiled() is not None
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


BACKENDS = ("auto", "numba", "scipy")


def resolve_backend(backend: str) -> str:
    if backend not in BACKENDS:
        raise ValueError(f"backend must be 'auto', 'numba' or 'scipy'; got {backend!r}")
    if backend == "numba" and compiled() is None:
        raise ValueError(
            "backend 'numba' needs numba, a dependency of slosh_bif that failed to import here: "
            "pip install numba (or use backend='scipy')"
        )
    if backend == "auto":
        return "numba" if compiled() is not None else "scipy"
    return backend


def _check(params, z0, tau0, tau1, rtol, atol, size):
    if not isinstance(params, Params):
        raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
    z0 = np.ascontiguousarray(z0, dtype=float)  # the compiled loops take contiguous arrays
    # math.isfinite over the list, not np.isfinite: on 4 or 29 numbers numpy's ufunc and reduction
    # cost 3 us, a sixth of a whole period of (9) at n = 6 (the integration benchmark's unit).
    if z0.shape != (size,) or not all(map(math.isfinite, z0.tolist())):
        raise ValueError(f"initial state must be {size} finite numbers; got {z0!r}")
    if not (math.isfinite(tau0) and math.isfinite(tau1) and tau1 > tau0):
        raise ValueError(f"need finite tau0 < tau1; got tau0 = {tau0}, tau1 = {tau1}")
    if not (0 < rtol < 1 and 0 < atol < 1):
        raise ValueError(f"rtol and atol must be in (0, 1); got rtol = {rtol}, atol = {atol}")
    return z0


_LAST_PARS = (None, None)  # (params, its vector): Params is immutable; sweeps call with one set many times


def kernel_parameters(params: Params, noise=None, sensitivities=None):
    """The compiled loops' parameter vector: (eps, beta, gamma, sigma, Abar, lam, chi, n, p), then
    the noise's table of (47) or the two sensitivity directions over ``REAL_FIELDS``."""
    global _LAST_PARS
    last = _LAST_PARS  # one read: threads tracing side by side replace it
    if noise is None and sensitivities is None and last[0] is params:
        return last[1]
    q = params
    pars = np.array([q.eps, q.beta, q.gamma, q.sigma, q.Abar, q.lam, q.chi, q.n, q.p], dtype=float)
    if sensitivities is not None:  # the pair kernel's two directions: unit vectors over REAL_FIELDS
        directions = np.zeros((2, len(REAL_FIELDS)))
        for slot, name in enumerate(sensitivities):
            directions[slot, REAL_FIELDS.index(name)] = 1.0
        return np.concatenate([pars, directions.ravel()])
    if noise is not None:
        return np.concatenate([pars, noise.table])
    _LAST_PARS = (params, pars)
    return pars


def _check_noise(noise, tau0, tau1):
    if noise is None:
        return
    if not isinstance(noise, BandLimitedNoise):
        raise TypeError(
            "noise must be a slosh_bif.flows.noise.BandLimitedNoise (see band_limited_noise); got "
            f"{type(noise).__name__}"
        )
    if tau0 < noise.t0 - 1e-9 or tau1 > noise.t0 + noise.duration + 1e-9:
        raise ValueError(
            f"the noise signal covers tau in [{noise.t0:g}, {noise.t0 + noise.duration:g}]; "
            f"the integration asks for [{tau0:g}, {tau1:g}]: draw it for the whole run"
        )


def scipy_rhs(which, pars):
    """The generated kernel as scipy's ``fun(t, y)`` (the fallback path: same equations)."""
    from slosh_bif.flows.smooth.dop853 import KERNELS  # numba's too, for the kernels it compiles

    raw = KERNELS[which]

    def fun(tau, z):
        out = np.empty(len(z))
        raw(tau, z, out, pars)
        return out

    return fun


def integrate(
    params: Params,
    z0,
    span: tuple,
    *,
    shooting: bool = False,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_steps: int = 2_000_000,
    backend: str = "auto",
    noise=None,
    sensitivities: tuple = DEFAULT_SENSITIVITIES,
) -> Integration:
    """Integrate (9) (``shooting=False``, z = y) or (9) with everything shooting needs over
    ``span = (tau0, tau1)``, as scipy's ``solve_ivp`` takes it.

    With ``shooting=True`` z = [y, Phi (row-major), dy/dp1, dy/dp2, int tr J] for the two
    parameters named by ``sensitivities`` (any two of ``REAL_FIELDS``); the step rule chooses the
    first step. ``noise`` (a :class:`~slosh_bif.flows.noise.BandLimitedNoise`) adds the random forcing of
    (47) (plain model only). Never raises on integration failure: ``success`` and ``message`` say
    what happened.
    """
    tau0, tau1 = span
    if noise is not None and shooting:
        raise ValueError("shooting needs the periodic forcing: noise is only for plain integration")
    which = "shooting" if shooting else ("plain" if noise is None else "noisy")
    z0 = _check(params, z0, tau0, tau1, rtol, atol, SHOOTING_SIZE if shooting else 4)
    _check_noise(noise, tau0, tau1)
    pair = None
    if shooting and tuple(sensitivities) != DEFAULT_SENSITIVITIES:
        which, pair = "pair", real_pair(sensitivities, "sensitivities")
    pars = kernel_parameters(params, noise, pair)
    if resolve_backend(backend) == "numba":
        z, steps, rejected, nfev, h, status = compiled().dop853_loop(
            WHICH[which],
            float(tau0),
            float(tau1),
            z0,
            pars,
            float(rtol),
            float(atol),
            0.0,  # the first step: the rule's choice
            int(max_steps),
            np.empty((0, 0)),  # no tape
            *TABLEAU,
        )
        return Integration(
            z, steps, rejected, nfev, h, status == OK, MESSAGES[status]
        )  # numba returns Python int and float
    from scipy.integrate import solve_ivp  # the fallback only: a third of a second to import

    fun = scipy_rhs(which, pars)
    with np.errstate(over="ignore", invalid="ignore"):  # trial steps deep in the wall may overflow
        sol = solve_ivp(fun, (tau0, tau1), z0, method="DOP853", rtol=rtol, atol=atol)
    steps = len(sol.t) - 1
    return Integration(
        sol.y[:, -1].copy(),
        steps,
        0,
        int(sol.nfev),
        math.nan,
        bool(sol.success),
        "ok" if sol.success else sol.message,
    )


def integrate_variations(
    params: Params, y0, t1: float, directions, pairs=(), triples=(), *, rtol=1e-11, atol=1e-13, backend="auto"
):
    """The flow of (9) from ``y0`` at tau = 0 to ``t1`` with its derivatives in the initial state
    (:mod:`slosh_bif.flows.smooth.variations`): the end of [y, Phi d for each of the real
    ``directions``, D2 phi[a, b] for each of the ``pairs`` (a, b), D3 phi[a, b, c] for each of the
    ``triples`` (a, b, c)], pairs and triples as indices of the directions (a triple's three pairs
    among the pairs). A one-line ValueError where the integration fails."""
    directions = np.atleast_2d(np.asarray(directions, dtype=float))
    pars = variation_parameters(kernel_parameters(params), len(directions), pairs, triples)
    z0 = np.zeros(variations_size(len(directions), len(pairs), len(triples)))
    z0[:4] = _check(params, y0, 0.0, t1, rtol, atol, 4)
    z0[4 : 4 + directions.size] = directions.ravel()
    if resolve_backend(backend) == "numba":
        z, _, _, _, _, status = compiled().dop853_loop(
            WHICH["variations"],
            0.0,
            float(t1),
            z0,
            pars,
            float(rtol),
            float(atol),
            0.0,
            2_000_000,
            np.empty((0, 0)),
            *TABLEAU,
        )
        if status != OK:
            raise ValueError(
                f"the variational equations of (9) were not integrated to {t1:g}: {MESSAGES[status]}"
            )
        return z
    from scipy.integrate import solve_ivp  # the fallback only

    with np.errstate(over="ignore", invalid="ignore"):
        run = solve_ivp(scipy_rhs("variations", pars), (0.0, t1), z0, method="DOP853", rtol=rtol, atol=atol)
    if not run.success:
        raise ValueError(f"the variational equations of (9) were not integrated to {t1:g}: {run.message}")
    return run.y[:, -1].copy()


def integrate_grid(
    params: Params,
    y0,
    taus,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    backend: str = "auto",
    noise=None,
    directions=None,
):
    """States of (9) at the increasing times ``taus`` (the first is the start), shape (len(taus), 4).

    ``noise`` adds the random forcing of (47) as in :func:`integrate`. ``directions``: two rows of
    weights over ``REAL_FIELDS`` (eps, beta, gamma, sigma, Abar, lam, chi); the states are then
    those of (9) with its variational equations, [y, Phi (row-major), dy/da, dy/db, int tr J]
    (shape (len(taus), 29)) from Phi = I and zero sensitivities at the first time, dy/da the
    derivative along the first row's direction in the parameters. Raises RuntimeError naming the
    time where the integration failed.
    """
    taus = np.ascontiguousarray(taus, dtype=float)
    if taus.ndim != 1 or len(taus) < 2 or not np.all(np.diff(taus) > 0):
        raise ValueError("taus must be at least two strictly increasing times")
    y0 = _check(params, y0, taus[0], taus[1], rtol, atol, 4)
    _check_noise(noise, taus[0], taus[-1])
    which = "plain" if noise is None else "noisy"
    pars = kernel_parameters(params, noise)
    if directions is not None:
        if noise is not None:
            raise ValueError("sensitivities need the periodic forcing: no noise with directions")
        directions = np.asarray(directions, dtype=float)
        if directions.shape != (2, len(REAL_FIELDS)) or not np.isfinite(directions).all():
            raise ValueError(f"directions must be 2 x {len(REAL_FIELDS)} finite weights over {REAL_FIELDS}")
        which, pars = "pair", np.concatenate([pars, directions.ravel()])
        y0 = np.concatenate([y0, np.eye(4).ravel(), np.zeros(SHOOTING_SIZE - 20)])
    out = np.empty((len(taus), len(y0)))
    out[0] = y0
    if resolve_backend(backend) == "scipy":
        from scipy.integrate import solve_ivp

        with np.errstate(over="ignore", invalid="ignore"):
            sol = solve_ivp(
                scipy_rhs(which, pars),
                (taus[0], taus[-1]),
                out[0],
                method="DOP853",
                rtol=rtol,
                atol=atol,
                t_eval=taus,
            )
        if not sol.success:
            raise RuntimeError(f"integration of (9) failed near tau = {sol.t[-1]:.6g}: {sol.message}")
        return sol.y.T.copy()
    states, reached, status = compiled().grid_loop(
        WHICH[which], taus, out[0], pars, float(rtol), float(atol), 2_000_000, *TABLEAU
    )
    if status != OK:
        raise RuntimeError(
            f"integration of (9) failed between tau = {taus[reached - 1]:.6g} and "
            f"{taus[reached]:.6g}: {MESSAGES[int(status)]}"
        )
    return states
