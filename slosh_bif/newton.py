"""Newton's method, once for the whole package: the continuation's corrector, Newton at a fixed
parameter, the fold of the restitution law (39) on the manifold and the steady states of (46) at
the end of S+ all iterate here, with one convention for failure.

A run never raises on failure: :class:`NewtonResult` says whether it converged, after how many
steps, and why it stopped (an iterate outside the domain, a residual that is not finite, a
singular Jacobian, a diverging iterate, too many steps). The callers differ only in what they
pass: the residual and its Jacobian, the convergence rule, the domain and how a step that leaves
it is treated (refused, or halved back into it), and a bound on each step.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

__all__ = ["CRITERIA", "NewtonSettings", "NewtonResult", "newton_loop"]

CRITERIA = ("step", "residual", "corrector", "lookahead")
"""How convergence is judged, with ``scale = 1 + |x|``:

* ``"step"``: the last update is below ``tol * scale`` (or the start is a solution to rounding),
  judged right after the update, without another residual;
* ``"residual"``: ``|F| <= tol * scale`` (for residuals that carry an integration's error, whose
  updates stall at that error);
* ``"corrector"``: after at least one update, ``|F|`` at the tolerance and the last update, or the
  next one predicted from quadratic convergence (``|dx_k|^2 / |dx_k-1|``), below ``tol * scale``;
  or, after three updates, ``|F| <= tol / 100`` (near a branch point the updates are rounding
  amplified by the condition number, while the residual still says done);
* ``"lookahead"``: as ``"corrector"``, and also done after at least one update when ``|F|`` is at
  the tolerance and the *next* update, solved from this iterate's residual and Jacobian, is below
  ``tol * scale``: the iterate is returned as it is, so its Jacobian (which the caller may reuse)
  belongs to it, and one evaluation of the residual is saved (a continuation's corrector thus
  stops after two evaluations where the strict rule takes three); and a run whose residual has
  not halved over three updates stops unconverged (a continuation then shortens its step
  instead of spending the remaining updates of a wandering run)."""


@dataclasses.dataclass(frozen=True)
class NewtonSettings:
    """``tol`` and ``criterion`` (one of :data:`CRITERIA`) judge convergence; at most ``max_iter``
    updates; a step that leaves the domain is halved up to ``halvings`` times."""

    tol: float = 1e-11
    max_iter: int = 30
    criterion: str = "step"
    halvings: int = 0

    def __post_init__(self):
        if self.criterion not in CRITERIA:
            raise ValueError(f"criterion must be one of {', '.join(CRITERIA)}; got {self.criterion!r}")


@dataclasses.dataclass(frozen=True)
class NewtonResult:
    """The last iterate, whether it converged, the updates taken, the last residual norm, a
    message saying why the run stopped, and whether it stopped for lack of progress (the
    ``"lookahead"`` rule: a run that would not have converged, not one that left the domain)."""

    x: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str
    stalled: bool = False


def _norm(v) -> float:
    """The 2-norm of a vector, as ``np.linalg.norm`` computes it (sqrt of the dot product), without
    its dispatch: a corrector takes a few per evaluation."""
    v = np.ravel(v)
    return math.sqrt(float(v @ v))


def _corrector_done(k, residual, step, previous, tol, scale) -> bool:
    if k == 0 or residual > max(tol, 1e3 * np.finfo(float).eps * scale):
        return False
    return (
        step <= tol * scale
        or (k > 1 and step * step / previous <= tol * scale)
        or (k > 2 and residual <= 1e-2 * tol)
    )


def newton_loop(
    residual,
    jacobian,
    x0,
    settings: NewtonSettings = NewtonSettings(),
    *,
    admissible=None,
    bound_step=None,
    solve=np.linalg.solve,
    domain: str = "the domain",
) -> NewtonResult:
    """Newton on ``residual(x) = 0`` from ``x0`` with the Jacobian ``jacobian(x)`` (formed only when
    a step is taken).

    ``settings``: the convergence rule and the step limits. ``admissible(x)``: whether x is in the
    domain (every iterate is checked); a step that leaves it is halved up to ``settings.halvings``
    times, and with none left the run stops. ``bound_step(x, dx)``: the update actually taken (a
    clipped one, say). ``solve(J, b)``: the linear solve (a least-squares one where a singular
    matrix is expected). ``domain`` names the domain in the message of a run that leaves it.
    """
    tol, max_iter, criterion = settings.tol, settings.max_iter, settings.criterion
    x = np.array(x0, dtype=float)
    F = np.full(1, np.nan)
    step = previous = math.inf
    norms = []

    def stop(converged, k, message, stalled=False):
        norm = float(np.linalg.norm(F)) if np.isfinite(F).all() else math.inf
        return NewtonResult(x, converged, k, norm, message, stalled)

    for k in range(max_iter + 1):
        if admissible is not None and not admissible(x):
            return stop(False, k, f"Newton left {domain} at iteration {k} (x = {x})")
        F = np.asarray(residual(x), dtype=float)
        if not np.isfinite(F).all():
            return stop(
                False, k, "the residual is not finite (an evaluation failed): no solution near this guess"
            )
        scale, norm = 1.0 + _norm(x), _norm(F)
        norms.append(norm)
        if criterion == "residual" and norm <= tol * scale:
            return stop(True, k, f"converged in {k} Newton steps")
        if criterion in ("corrector", "lookahead") and _corrector_done(k, norm, step, previous, tol, scale):
            return stop(True, k, f"converged in {k} Newton steps")
        if criterion == "step" and k == 0 and norm <= 1e3 * np.finfo(float).eps * scale:
            return stop(True, 0, "the start is a solution")  # a closed form, say: no Jacobian needed
        if k == max_iter:
            break
        if criterion == "lookahead" and k >= 3 and norm > 0.5 * norms[k - 3]:
            message = f"no progress: |F| = {norm:.3g} after {k} Newton steps, not half of three before"
            return stop(False, k, message, stalled=True)
        J = jacobian(x)
        if not np.isfinite(J).all():
            return stop(False, k, f"the Jacobian is not finite at iteration {k}")
        try:
            dx = solve(J, -F)
        except np.linalg.LinAlgError:
            return stop(False, k, f"the Jacobian is singular at iteration {k}: a fold or branch point")
        if criterion == "lookahead" and k > 0 and norm <= tol and _norm(dx) <= tol * scale:
            return stop(True, k, f"converged in {k} Newton steps (the next one below the tolerance)")
        if bound_step is not None:
            dx = bound_step(x, dx)
        for _ in range(settings.halvings):
            if admissible(x + dx):
                break
            dx = 0.5 * dx
        previous, step = step, _norm(dx)
        x = x + dx
        if not np.isfinite(x).all():
            return stop(False, k + 1, "Newton diverged (non-finite iterate)")
        if (
            criterion == "step" and step <= tol * (1.0 + _norm(x)) and (admissible is None or admissible(x))
        ):  # (the other rules check the new iterate at the top of the loop)
            return stop(True, k + 1, f"converged in {k + 1} Newton steps")
    return stop(
        False, max_iter, f"no convergence in {max_iter} Newton steps (last |F| = {np.linalg.norm(F):.3g})"
    )
