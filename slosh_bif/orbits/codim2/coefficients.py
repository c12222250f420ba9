"""The normal-form coefficient along a curve of orbit bifurcations of (9) or (8), and its zeros as
codimension-2 points: the degenerate flip GPD on a PD curve (b = 0), the degenerate
symmetry-breaking pitchfork DBP on a BP curve (the flip of the half-period map with b = 0) and
the Chenciner point CH on an NS curve (the first Lyapunov coefficient d = 0); the curve's boundary
is soft on one side of such a point and hard on the other. A fold is a jump all along an LP curve;
its own quadratic coefficient is the curve's cusp test (CP).

The coefficients are those of :func:`~slosh_bif.orbits.map_derivatives.criticality` (Kuznetsov's
normal forms of maps; the map's derivatives from the generated variational equations of (9) or the
jets through (8)'s impacts), computed after the curve is traced at every :data:`STRIDE`-th point,
at both ends, beside the curve's own codimension-2 points, and at every point between two computed
ones of opposite sign. Each is integrated at two tolerances and kept where the two agree
(:func:`_settled`): the coefficient is a small difference of large terms where the wall is stiff,
and its sign at one tolerance can be the integration's error; a point where it does not settle is
undetermined and places no zero. A change of sign between two settled neighbours is located on the
curve: points of the curve on planes across the chord between the two (each a corrector solve)
where the coefficient is evaluated, the plane moved by regula falsi (Illinois) until the bracket
is below :data:`ZERO_TOL` in arclength or the coefficient below its own accuracy; linear
interpolation between the two (to about the curve's step) only where that fails, and the point's
message says which. No zero is placed where the coefficient grows towards the change instead of
falling (a pole, where a second multiplier reaches the unit circle: LPPD, PDNS, R1-R4, BPLP); a
zero closer to such a point than the curve's next point is not seen. Points between computed ones
carry the interpolated coefficient and the nearer computed one's judgement (undetermined beside a
point whose coefficient could not be computed). Evaluating it at every point, as a test function,
cost half as much again as the curve itself at one tolerance (1e-9)."""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import ContinuationOptions, SpecialPoint
from slosh_bif.continuation.corrector import correct
from slosh_bif.orbits.map_derivatives import FINE_RTOL, RTOL, FlowDerivatives, criticality, settle
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = [
    "COEFFICIENT_KINDS",
    "DEGENERATE",
    "STRIDE",
    "CURVE_RTOL",
    "ZERO_TOL",
    "boundary",
    "curve_coefficients",
]

STRIDE = 3  # the coefficient at every third point of a curve (and wherever it changes sign)
# The variational equations' tolerance on a curve, that of a branch's verdicts: at 1e-9 the Fig. 10
# pitchfork curve's coefficient (n = 50, sigma 1.7-2.0, b ~ 0.003-0.02) came out with the wrong sign
# (-0.33 where it is +0.020), at 1e-11 within 10 % of its limit under refinement.
CURVE_RTOL = RTOL  # zeros are located at FINE_RTOL
ZERO_TOL = 1e-8  # a located zero's bracket in arclength
_ZERO_ITERATIONS = 16
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
    strong resonance) or its coefficient did not settle under refinement; '' where no coefficient
    was computed."""
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
    point's normal form is valid (0 where it is not, or could not be computed). ``derivatives``:
    the map derivatives of the curve's model (:class:`FlowDerivatives` for (9)'s shooting, the
    default; (8)'s curves pass theirs).
    ``(branch, {})`` for kinds without one (LP) and for a model without map derivatives."""
    kind = problem.kind
    if derivatives is None and isinstance(problem.orbits, ShootingProblem):
        derivatives = FlowDerivatives
    if kind not in COEFFICIENT_KINDS or derivatives is None or not len(branch):
        return branch, {}
    n = len(branch)
    value, valid, settled = np.full(n, np.nan), np.zeros(n), np.ones(n, dtype=bool)

    def at(i):
        if np.isnan(value[i]) and not valid[i] < 0:
            nf, settled[i] = _settled(problem, branch.x[i], branch.p[i], derivatives)
            value[i] = np.nan if nf is None else nf.coefficient
            valid[i] = 1.0 if nf is not None and nf.status == "ok" and settled[i] else -1.0
        return value[i]

    # also beside the curve's own codimension-2 points: a pole there (a second multiplier on the
    # unit circle) and a zero just past it change the sign twice between two strided points
    beside = {i for sp in branch.special if sp.kind != "END" for i in range(sp.index - 1, sp.index + 3)}
    computed = sorted(set(range(0, n, STRIDE)) | {n - 1} | {i for i in beside if 0 <= i < n})
    for i in computed:
        at(i)
    zeros = []
    for lo, hi in zip(computed, computed[1:]):
        if not value[lo] * value[hi] < 0:
            continue
        for i in range(lo + 1, hi):
            at(i)
        for j in range(lo, hi):  # no change placed at a point not evaluated or not settled
            if not (value[j] * value[j + 1] < 0 and settled[j] and settled[j + 1]):
                continue
            outer = [abs(at(i)) for i in (j - 1, j + 2) if 0 <= i < n]
            if outer and max(abs(value[j]), abs(value[j + 1])) > max(outer):
                continue  # grows towards the change: a pole
            zeros.append(_zero(problem, branch, j, value, derivatives))
    done, evaluated = np.isfinite(value), valid != 0
    s = branch.arclength
    # a point whose coefficient could not be computed judges its half of each interval (undetermined)
    judged = np.interp(s, s[evaluated], (valid[evaluated] > 0).astype(float)).round()
    out = {"coefficient": np.interp(s, s[done], value[done]) if done.any() else value, "judged": judged}
    special = sorted([*branch.special, *zeros], key=lambda sp: (sp.index, sp.kind == "END"))
    return dataclasses.replace(branch, special=tuple(special)), out


def _settled(problem, x, p, derivatives):
    """(NormalForm or None, whether its coefficient has settled):
    :func:`~slosh_bif.orbits.map_derivatives.settle` on the curve point's normal form."""
    return settle(
        lambda rtol: _normal_form(problem, x, p, derivatives, rtol),
        _normal_form(problem, x, p, derivatives),
        exact=getattr(derivatives, "exact", False),
    )


def _zero(problem, branch, j, value, derivatives) -> SpecialPoint:
    """The coefficient's zero between curve points j and j + 1: located on the curve, or by linear
    interpolation where that fails (the message says which)."""
    label = COEFFICIENT_KINDS[problem.kind]
    located = _located(problem, branch, j, value, derivatives)
    if located is None:
        t = value[j] / (value[j] - value[j + 1])
        u = (1 - t) * np.append(branch.x[j], branch.p[j]) + t * np.append(branch.x[j + 1], branch.p[j + 1])
        how = "by linear interpolation (not located on the curve)"
    else:
        u, width = located
        how = f"located on the curve to {width:.1g} in arclength"
    return SpecialPoint(
        label,
        j,
        float(u[-1]),
        u[:-1],
        (float(branch.p[j]), float(branch.p[j + 1])),
        f"{DEGENERATE[label]}; between curve points {j} and {j + 1}, {how}",
    )


def _located(problem, branch, j, value, derivatives):
    """(u, bracket width in arclength) of the zero between points j and j + 1 by regula falsi
    (Illinois) over the planes across their chord, each point corrected onto the curve: the
    bracket's end with the smaller coefficient, the bracket's width its precision (the
    coefficient's own error, not the iterations, may bound it); None where a corrector or a
    coefficient fails."""
    ends = np.array([np.append(branch.x[i], branch.p[i]) for i in (j, j + 1)])
    chord = float(np.linalg.norm(ends[1] - ends[0]))
    try:
        options = ContinuationOptions(**branch.options)
    except (TypeError, ValueError):
        return None
    if chord == 0:
        return None
    normal = (ends[1] - ends[0]) / chord
    # each end: [t along the chord, coefficient, its weight for regula falsi, point]
    low, high = [0.0, value[j], value[j], ends[0]], [1.0, value[j + 1], value[j + 1], ends[1]]
    floor = 1e-7 * max(abs(value[j]), abs(value[j + 1]))  # the coefficient's accuracy at best
    problem.init_borders(branch.x[j], branch.p[j])
    kept = None
    for _ in range(_ZERO_ITERATIONS):
        t = (low[0] * high[2] - high[0] * low[2]) / (high[2] - low[2])
        u, _ = correct(problem, (1 - t) * ends[0] + t * ends[1], normal, options, strict=True)
        if u is None:
            return None
        nf = _normal_form(problem, u[:-1], u[-1], derivatives, FINE_RTOL)
        if nf is None or not np.isfinite(nf.coefficient):
            return None
        c = nf.coefficient
        if abs(c) <= floor:
            return u, floor * chord / abs(value[j + 1] - value[j])  # its accuracy over its slope
        near, far = (low, high) if (c > 0) == (low[1] > 0) else (high, low)
        near[:] = [t, c, c, u]
        if kept is near:  # the same end moved twice: the other's weight halved (Illinois)
            far[2] /= 2
        kept = near
        if (high[0] - low[0]) * chord <= ZERO_TOL:
            break
    best = low if abs(low[1]) <= abs(high[1]) else high
    return best[3], (high[0] - low[0]) * chord


def _normal_form(problem, x, p, derivatives, rtol=CURVE_RTOL):
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
            rtol=rtol,
            derivatives=derivatives,
        )
    except ValueError:
        return None
