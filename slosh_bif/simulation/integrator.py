"""Compiled integration of the smooth model (9): DOP853 in a numba hot loop, scipy as the fallback.

The method is the explicit Runge-Kutta pair DOP853 of Hairer, Norsett and Wanner with exactly the
error norm, step-size control and initial-step rule of scipy's ``solve_ivp(method="DOP853")``; its
Butcher coefficients are read from scipy at import, so both backends run the same method and
differ only in rounding and in where output points fall. The right-hand sides are the scalar
kernels that the sympy derivation writes (``_generated/kernels.py``): (9) alone, and (9) with its
variational equations, parameter sensitivities and the Liouville integral for shooting; a third,
(9) with the random forcing of (47), adds the noise spline of :mod:`slosh_bif.simulation.noise` where
cos(tau) enters.

Why: one period of (9) at n = 50 takes thousands of steps (the wall term chi w^101 is stiff in an
explicit method's eyes), and a Python right-hand side called from scipy's stepper spends tens of
microseconds a step in interpreter overhead. The compiled loop spends about a microsecond.

``backend="auto"`` takes numba when it is installed (the ``fast`` extra) and scipy otherwise;
``"numba"`` and ``"scipy"`` force one. Both return the same :class:`Integration` record.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.integrate._ivp import dop853_coefficients as _dop

from slosh_bif.model._generated import kernels as _kernels
from slosh_bif.model.params import REAL_FIELDS, Params, real_pair
from slosh_bif.simulation.noise import BandLimitedNoise

try:  # the optional ``fast`` extra
    import numba
except ImportError:  # pragma: no cover - exercised on machines without numba
    numba = None

__all__ = ["HAVE_NUMBA", "Integration", "integrate", "integrate_grid", "SHOOTING_SIZE", "resolve_backend", "DEFAULT_SENSITIVITIES"]

HAVE_NUMBA = numba is not None
SHOOTING_SIZE = 29  # [y, Phi, dy/dp1, dy/dp2, int tr J]
DEFAULT_SENSITIVITIES = ("sigma", "Abar")  # the dedicated kernel's pair; any other pair takes the pair kernel

_STAGES = _dop.N_STAGES
_A = np.ascontiguousarray(_dop.A[:_STAGES, :_STAGES])
_B = np.ascontiguousarray(_dop.B)
_C = np.ascontiguousarray(_dop.C[:_STAGES])
_E3 = np.ascontiguousarray(_dop.E3)
_E5 = np.ascontiguousarray(_dop.E5)

# Status codes of the compiled loop.
_OK, _MAX_STEPS, _TOO_SMALL, _NOT_FINITE = 0, 1, 2, 3
_MESSAGES = {
    _OK: "ok",
    _MAX_STEPS: "step limit reached",
    _TOO_SMALL: "step size fell below the rounding limit",
    _NOT_FINITE: "the solution became non-finite",
}


@dataclasses.dataclass(frozen=True)
class Integration:
    """End state of one integration and what it cost.

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


def _jit(function):
    """numba.njit with an on-disk cache when numba is there; the plain function otherwise."""
    # error_model="numpy": a division by zero in a trial step gives inf/NaN (then the step is rejected)
    # instead of raising, as in the scipy path.
    return numba.njit(cache=True, error_model="numpy")(function) if HAVE_NUMBA else function


@_jit
def _rms(v, scale):
    total = 0.0
    for i in range(v.shape[0]):
        r = v[i] / scale[i]
        total += r * r
    return math.sqrt(total / v.shape[0])


@_jit
def _grid_loop(which, taus, z0, pars, rtol, atol, max_steps, A, B, C, E3, E5):
    """States at every time of ``taus``, the step size carried from one interval to the next."""
    out = np.empty((taus.shape[0], z0.shape[0]))
    out[0] = z0
    h = 0.0
    for k in range(1, taus.shape[0]):
        z, steps, rejected, nfev, h, status = _dop853_loop(which, taus[k - 1], taus[k], out[k - 1], pars, rtol, atol, h, max_steps, A, B, C, E3, E5)
        if status != 0:
            return out, k, status
        out[k] = z
    return out, taus.shape[0], 0


_NOISE_AT = 9  # pars[9:] holds the noise spline table (noise.BandLimitedNoise.table) for "noisy"


def _noise_force(tau, pars):
    """F_w(tau) from the spline table in ``pars[9:]`` (the scalar twin of BandLimitedNoise.__call__)."""
    t0 = pars[_NOISE_AT]
    dt = pars[_NOISE_AT + 1]
    m = int(pars[_NOISE_AT + 2])
    degree = int(pars[_NOISE_AT + 3])
    i = int((tau - t0) / dt)
    i = min(max(i, 0), m - 1)
    s = tau - (t0 + i * dt)
    k = _NOISE_AT + 4 + (degree + 1) * i
    value = pars[k]
    for j in range(1, degree + 1):
        value = value * s + pars[k + j]
    return value


def _noisy_kernel_py(tau, y, out, pars):
    """(9) with the forcing eps*(Abar cos tau + F_w(tau)) of (47): F_w enters where cos tau does."""
    _plain_kernel(tau, y, out, pars)
    force = pars[0] * _noise_force(tau, pars)
    out[1] += force
    out[3] += force


_RAW = {"plain": _kernels.smooth_rhs_kernel, "shooting": _kernels.smooth_shooting_kernel, "pair": _kernels.smooth_pair_kernel}
_WHICH = {"plain": 0, "shooting": 1, "noisy": 2, "pair": 3}
_plain_kernel = _jit(_RAW["plain"])
_shooting_kernel = _jit(_RAW["shooting"])
_pair_kernel = _jit(_RAW["pair"])
_noise_force = _jit(_noise_force)
_RAW["noisy"] = _noisy_kernel_py
_noisy_kernel = _jit(_noisy_kernel_py)


@_jit
def _kernel(which, tau, z, out, pars):
    # One entry point with a switch rather than the kernel as an argument: numba cannot cache a
    # function that takes another compiled function as argument, and recompiling costs ~1 s a process.
    if which == 0:
        _plain_kernel(tau, z, out, pars)
    elif which == 1:
        _shooting_kernel(tau, z, out, pars)
    elif which == 3:
        _pair_kernel(tau, z, out, pars)
    else:
        _noisy_kernel(tau, z, out, pars)


@_jit
def _dop853_loop(which, t0, t1, z0, pars, rtol, atol, h, max_steps, A, B, C, E3, E5):
    """The hot loop; plain Python that numba compiles (see :func:`_compiled`)."""
    n = z0.shape[0]
    K = np.empty((13, n))
    z = z0.copy()
    znew = np.empty(n)
    tmp = np.empty(n)
    scale = np.empty(n)
    _kernel(which, t0, z, K[0], pars)
    nfev = 1
    span = t1 - t0
    if h <= 0.0:  # scipy's initial step (Hairer, Norsett & Wanner II.4) for an order-7 estimate
        for i in range(n):
            scale[i] = atol + abs(z[i]) * rtol
        d0 = _rms(z, scale)
        d1 = _rms(K[0], scale)
        h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h0 = min(h0, span)
        for i in range(n):
            tmp[i] = z[i] + h0 * K[0, i]
        _kernel(which, t0 + h0, tmp, K[1], pars)
        nfev += 1
        for i in range(n):
            znew[i] = K[1, i] - K[0, i]
        d2 = _rms(znew, scale) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h = min(100 * h0, h1, span)
    t = t0
    steps = 0
    rejected = 0
    status = 0
    while t < t1:
        if steps >= max_steps:
            status = 1
            break
        step_rejected = False
        while True:
            min_step = 10 * abs(np.nextafter(t, np.inf) - t)
            if h < min_step:
                status = 2
                break
            t_new = t + h
            if t_new > t1:
                t_new = t1
            hh = t_new - t
            for s in range(1, 12):
                if n > 4:  # the shooting system: row by row of K, contiguous and vectorised, zeros skipped (40 % faster at 29 components; 20 % slower at 4)
                    for i in range(n):
                        tmp[i] = 0.0
                    for j in range(s):
                        a = A[s, j]
                        if a != 0.0:
                            for i in range(n):
                                tmp[i] += a * K[j, i]
                    for i in range(n):
                        tmp[i] = z[i] + hh * tmp[i]
                else:
                    for i in range(n):
                        acc = 0.0
                        for j in range(s):
                            acc += A[s, j] * K[j, i]
                        tmp[i] = z[i] + hh * acc
                _kernel(which, t + C[s] * hh, tmp, K[s], pars)
            for i in range(n):
                acc = 0.0
                for j in range(12):
                    acc += B[j] * K[j, i]
                znew[i] = z[i] + hh * acc
            _kernel(which, t_new, znew, K[12], pars)
            nfev += 12
            err5 = 0.0
            err3 = 0.0
            for i in range(n):
                sc = atol + max(abs(z[i]), abs(znew[i])) * rtol
                e5 = 0.0
                e3 = 0.0
                for j in range(13):
                    e5 += E5[j] * K[j, i]
                    e3 += E3[j] * K[j, i]
                e5 /= sc
                e3 /= sc
                err5 += e5 * e5
                err3 += e3 * e3
            if err5 == 0.0 and err3 == 0.0:
                error = 0.0
            else:
                error = abs(hh) * err5 / math.sqrt((err5 + 0.01 * err3) * n)
            if error < 1.0:  # NaN compares false: a non-finite trial step is rejected
                factor = 10.0 if error == 0.0 else min(10.0, 0.9 * error ** (-1.0 / 8.0))
                if step_rejected:
                    factor = min(1.0, factor)
                h = hh * factor
                break
            h = hh * max(0.2, 0.9 * error ** (-1.0 / 8.0)) if error == error else hh * 0.2
            step_rejected = True
            rejected += 1
        if status != 0:
            break
        t = t_new
        for i in range(n):
            z[i] = znew[i]
            K[0, i] = K[12, i]
        steps += 1
        if not np.isfinite(z[0]):
            status = 3
            break
    return z, steps, rejected, nfev, h, status


def resolve_backend(backend: str) -> str:
    if backend not in ("auto", "numba", "scipy"):
        raise ValueError(f"backend must be 'auto', 'numba' or 'scipy'; got {backend!r}")
    if backend == "numba" and not HAVE_NUMBA:
        raise ValueError("backend 'numba' needs numba, a dependency of slosh_bif that failed to import here: pip install numba (or use backend='scipy')")
    if backend == "auto":
        return "numba" if HAVE_NUMBA else "scipy"
    return backend


def _check(params, z0, tau0, tau1, rtol, atol, size):
    if not isinstance(params, Params):
        raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
    z0 = np.asarray(z0, dtype=float)
    if z0.shape != (size,) or not np.all(np.isfinite(z0)):
        raise ValueError(f"initial state must be {size} finite numbers; got {z0!r}")
    if not (math.isfinite(tau0) and math.isfinite(tau1) and tau1 > tau0):
        raise ValueError(f"need finite tau0 < tau1; got tau0 = {tau0}, tau1 = {tau1}")
    if not (0 < rtol < 1 and 0 < atol < 1):
        raise ValueError(f"rtol and atol must be in (0, 1); got rtol = {rtol}, atol = {atol}")
    return z0


def _pars(params: Params, noise=None, sensitivities=None):
    q = params
    pars = np.array([q.eps, q.beta, q.gamma, q.sigma, q.Abar, q.lam, q.chi, q.n, q.p], dtype=float)
    if sensitivities is not None:  # the pair kernel's two directions: unit vectors over REAL_FIELDS
        directions = np.zeros((2, len(REAL_FIELDS)))
        for slot, name in enumerate(sensitivities):
            directions[slot, REAL_FIELDS.index(name)] = 1.0
        return np.concatenate([pars, directions.ravel()])
    return pars if noise is None else np.concatenate([pars, noise.table])


def _check_noise(noise, tau0, tau1):
    if noise is None:
        return
    if not isinstance(noise, BandLimitedNoise):
        raise TypeError(f"noise must be a slosh_bif.simulation.noise.BandLimitedNoise (see band_limited_noise); got {type(noise).__name__}")
    if tau0 < noise.t0 - 1e-9 or tau1 > noise.t0 + noise.duration + 1e-9:
        raise ValueError(
            f"the noise signal covers tau in [{noise.t0:g}, {noise.t0 + noise.duration:g}]; "
            f"the integration asks for [{tau0:g}, {tau1:g}]: draw it for the whole run"
        )


def _scipy_rhs(which, pars):
    """The generated kernel as scipy's ``fun(t, y)`` (the fallback path: same equations)."""
    raw = _RAW[which]

    def fun(tau, z):
        out = np.empty(len(z))
        raw(tau, z, out, pars)
        return out

    return fun


def integrate(
    params: Params,
    z0,
    tau0: float,
    tau1: float,
    *,
    shooting: bool = False,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    h0: float = 0.0,
    max_steps: int = 2_000_000,
    backend: str = "auto",
    noise=None,
    sensitivities: tuple = DEFAULT_SENSITIVITIES,
) -> Integration:
    """Integrate (9) (``shooting=False``, z = y) or (9) with everything shooting needs from tau0 to tau1.

    With ``shooting=True`` z = [y, Phi (row-major), dy/dp1, dy/dp2, int tr J] for the two
    parameters named by ``sensitivities`` (any two of ``REAL_FIELDS``). ``h0 > 0`` warm-starts the step size (pass the previous call's ``h_next``); 0 lets the rule
    choose. ``noise`` (a :class:`~slosh_bif.simulation.noise.BandLimitedNoise`) adds the random forcing of
    (47) (plain model only). Never raises on integration failure: ``success`` and ``message`` say
    what happened.
    """
    if noise is not None and shooting:
        raise ValueError("shooting needs the periodic forcing: noise is only for plain integration")
    which = "shooting" if shooting else ("plain" if noise is None else "noisy")
    z0 = _check(params, z0, tau0, tau1, rtol, atol, SHOOTING_SIZE if shooting else 4)
    _check_noise(noise, tau0, tau1)
    pair = None
    if shooting and tuple(sensitivities) != DEFAULT_SENSITIVITIES:
        which, pair = "pair", real_pair(sensitivities, "sensitivities")
    pars = _pars(params, noise, pair)
    if resolve_backend(backend) == "numba":
        z, steps, rejected, nfev, h, status = _dop853_loop(_WHICH[which], float(tau0), float(tau1), z0, pars, float(rtol), float(atol), float(h0), int(max_steps), _A, _B, _C, _E3, _E5)
        return Integration(z, int(steps), int(rejected), int(nfev), float(h), status == _OK, _MESSAGES[int(status)])
    fun = _scipy_rhs(which, pars)
    with np.errstate(over="ignore", invalid="ignore"):  # trial steps deep in the wall may overflow
        sol = solve_ivp(fun, (tau0, tau1), z0, method="DOP853", rtol=rtol, atol=atol, first_step=h0 or None)
    steps = len(sol.t) - 1
    return Integration(sol.y[:, -1].copy(), steps, 0, int(sol.nfev), math.nan, bool(sol.success), "ok" if sol.success else sol.message)


def integrate_grid(params: Params, y0, taus, *, rtol: float = 1e-10, atol: float = 1e-12, backend: str = "auto", noise=None):
    """States of (9) at the increasing times ``taus`` (the first is the start), shape (len(taus), 4).

    ``noise`` adds the random forcing of (47) as in :func:`integrate`. Raises RuntimeError naming
    the time where the integration failed.
    """
    taus = np.asarray(taus, dtype=float)
    if taus.ndim != 1 or len(taus) < 2 or not np.all(np.diff(taus) > 0):
        raise ValueError("taus must be at least two strictly increasing times")
    out = np.empty((len(taus), 4))
    out[0] = _check(params, y0, taus[0], taus[1], rtol, atol, 4)
    _check_noise(noise, taus[0], taus[-1])
    which = "plain" if noise is None else "noisy"
    pars = _pars(params, noise)
    if resolve_backend(backend) == "scipy":
        with np.errstate(over="ignore", invalid="ignore"):
            sol = solve_ivp(_scipy_rhs(which, pars), (taus[0], taus[-1]), out[0], method="DOP853", rtol=rtol, atol=atol, t_eval=taus)
        if not sol.success:
            raise RuntimeError(f"integration of (9) failed near tau = {sol.t[-1]:.6g}: {sol.message}")
        return sol.y.T.copy()
    states, reached, status = _grid_loop(_WHICH[which], taus, out[0], pars, float(rtol), float(atol), 2_000_000, _A, _B, _C, _E3, _E5)
    if status != _OK:
        raise RuntimeError(f"integration of (9) failed between tau = {taus[reached - 1]:.6g} and {taus[reached]:.6g}: {_MESSAGES[int(status)]}")
    return states
