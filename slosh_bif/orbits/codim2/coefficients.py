"""The normal-form coefficient along a curve of orbit bifurcations of (9) or (8), and its zeros as
codimension-2 points: the degenerate flip GPD on a PD curve (b = 0), the degenerate
symmetry-breaking pitchfork DBP on a BP curve (the flip of the half-period map with b = 0) and
the Chenciner point CH on an NS curve (the first Lyapunov coefficient d = 0); the curve's boundary
is soft on one side of such a point and hard on the other. A fold is a jump all along an LP curve;
its own quadratic coefficient is the curve's cusp test (CP).

The coefficients are those of :func:`~slosh_bif.orbits.map_derivatives.criticality` (Kuznetsov's
normal forms of maps; the map's derivatives from the generated variational equations of (9) or
the jets through (8)'s impacts), computed after the curve is traced at every :data:`STRIDE`-th
point and at both ends, and at every point
between two computed ones of opposite sign: between the pair of neighbours where it changes sign
the zero is placed by linear interpolation (to about the curve's step, not to the 1e-9 of the
test-function points), unless the coefficient grows towards the change instead of falling (a
pole, where a second multiplier reaches the unit circle: LPPD, PDNS, R1-R4). Points between
computed ones carry the interpolated coefficient. Evaluating it at every point, as a test
function, would cost half as much again as the curve itself."""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import SpecialPoint
from slosh_bif.orbits.map_derivatives import FlowDerivatives, criticality
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = ["COEFFICIENT_KINDS", "DEGENERATE", "STRIDE", "CURVE_RTOL", "boundary", "curve_coefficients"]

STRIDE = 3  # the coefficient at every third point of a curve (and wherever it changes sign)
CURVE_RTOL = 1e-9  # the variational equations' tolerance on a curve: the coefficient to about 1e-7
COEFFICIENT_KINDS = {"PD": "GPD", "BP": "DBP", "NS": "CH"}
_EITHER_SIDE = "soft on one side, hard on the other"
DEGENERATE = {
    "GPD": f"degenerate period doubling: the flip's cubic coefficient vanishes ({_EITHER_SIDE})",
    "DBP": f"degenerate pitchfork: the symmetry breaking's cubic coefficient vanishes ({_EITHER_SIDE})",
    "CH": f"Chenciner point: the torus bifurcation's first Lyapunov coefficient vanishes ({_EITHER_SIDE})",
}


def boundary(kind: str, coefficient, judged) -> np.ndarray:
    """Per curve point, how stability is lost there: ``jump`` on an LP curve (a fold always is),
    ``soft`` or ``hard`` by the sign of the coefficient (b > 0 soft at a PD or BP, d < 0 at an NS),
    ``undetermined`` where the point's normal form is not valid (near a codimension-2 point or a
    strong resonance); '' where no coefficient was computed."""
    coefficient = np.asarray(coefficient, dtype=float)
    judged = np.asarray(judged, dtype=float) > 0
    if kind == "LP":
        return np.full(coefficient.shape, "jump", dtype="<U12")
    soft = coefficient > 0 if kind in ("PD", "BP") else coefficient < 0
    out = np.where(soft, "soft", "hard").astype("<U12")
    out[~judged | ~np.isfinite(coefficient)] = "undetermined"
    return out


def curve_coefficients(problem, branch, derivatives=None):
    """(branch with the coefficient's zeros added to its special points, {"coefficient": ...,
    "judged": ...}) for a traced curve (``problem`` its MinAugCurveProblem): the coefficient per
    point (interpolated in arclength between computed ones) and 1 where the nearest computed
    point's normal form is valid. ``derivatives``: the map derivatives of the curve's model
    (:class:`FlowDerivatives` for (9)'s shooting, the default; (8)'s curves pass theirs).
    ``(branch, {})`` for kinds without one (LP) and for a model without map derivatives."""
    kind = problem.kind
    if derivatives is None and isinstance(problem.orbits, ShootingProblem):
        derivatives = FlowDerivatives
    if kind not in COEFFICIENT_KINDS or derivatives is None or not len(branch):
        return branch, {}
    n = len(branch)
    value, valid = np.full(n, np.nan), np.zeros(n)

    def at(i):
        if np.isnan(value[i]) and not valid[i] < 0:
            nf = _normal_form(problem, branch.x[i], branch.p[i], derivatives)
            value[i] = np.nan if nf is None else nf.coefficient
            valid[i] = 1.0 if nf is not None and nf.status == "ok" else -1.0
        return value[i]

    computed = sorted(set(range(0, n, STRIDE)) | {n - 1})
    for i in computed:
        at(i)
    zeros = []
    for lo, hi in zip(computed, computed[1:]):
        if not value[lo] * value[hi] < 0:
            continue
        for i in range(lo + 1, hi):
            at(i)
        j = next((i for i in range(lo, hi) if value[i] * value[i + 1] < 0), None)
        if j is None:  # a point between could not be evaluated: the change is not placed
            continue
        outer = [abs(at(i)) for i in (j - 1, j + 2) if 0 <= i < n]
        if outer and max(abs(value[j]), abs(value[j + 1])) > max(outer):
            continue  # grows towards the change: a pole
        zeros.append(_zero(problem, branch, j, value))
    done = np.isfinite(value)
    s = branch.arclength
    out = {
        "coefficient": np.interp(s, s[done], value[done]) if done.any() else value,
        "judged": np.interp(s, s[done], (valid[done] > 0).astype(float)).round() if done.any() else valid,
    }
    special = sorted([*branch.special, *zeros], key=lambda sp: (sp.index, sp.kind == "END"))
    return dataclasses.replace(branch, special=tuple(special)), out


def _zero(problem, branch, j, value) -> SpecialPoint:
    """The coefficient's zero between curve points j and j + 1, by linear interpolation."""
    t = value[j] / (value[j] - value[j + 1])
    x = (1 - t) * branch.x[j] + t * branch.x[j + 1]
    p = (1 - t) * branch.p[j] + t * branch.p[j + 1]
    label = COEFFICIENT_KINDS[problem.kind]
    return SpecialPoint(
        label,
        j,
        float(p),
        x,
        (float(branch.p[j]), float(branch.p[j + 1])),
        f"{DEGENERATE[label]}; between curve points {j} and {j + 1}, by linear interpolation",
    )


def _normal_form(problem, x, p, derivatives):
    """The NormalForm of the curve point (x, p) of ``problem``, or None where the map's
    derivatives cannot be computed there (not integrated; (8)'s map not smooth)."""
    s = problem.orbits
    try:
        return criticality(
            problem.params_at(x, p),
            x[:4],
            problem.kind,
            period=2 * np.pi * s.period_multiple,
            symmetric=problem.symmetric,
            rtol=CURVE_RTOL,
            derivatives=derivatives,
        )
    except ValueError:
        return None
