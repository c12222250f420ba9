"""How a direction of continuation ends: at a parameter bound, after failed steps, at a domain's
edge or where the steps stall, each end marked on its last point with its reason."""

from __future__ import annotations

import numpy as np

from slosh_bif.continuation.branch import END
from slosh_bif.continuation.corrector import (
    Point,
    in_domain,
    make_point,
    newton,
)
from slosh_bif.continuation.options import (
    BOUND,
    EDGE,
    STALL,
    ConvergenceError,
)
from slosh_bif.continuation.problem import capabilities

__all__ = [
    "end_on_bound",
    "end_after_failures",
    "mark_end",
    "stalls",
    "at_named_edge",
    "edge_point",
    "bound_message",
]


def bound_message(bound, opts):
    return f"{BOUND} {'p_max' if bound == opts.p_max else 'p_min'} = {bound}"


def end_on_bound(problem, points, b_u, opts):
    """End at the bound that the corrected point b_u overshot: the point with p = bound between
    the last point and b_u (Newton at fixed p from the chord, else from b_u or the last point), or
    the last point itself when it is on the bound; or at the domain's edge, on the last point,
    where Newton fails at the bound from all three and the chord's point there lies outside the
    domain. Returns the end's reason."""
    a = points[-1]
    bound = opts.p_max if b_u[-1] > opts.p_max else opts.p_min
    if a.u[-1] == bound:  # a start on the bound is itself the end (not a second copy of it)
        mark_end(a, BOUND, bound_message(bound, opts))
        return BOUND
    w = (bound - a.u[-1]) / (b_u[-1] - a.u[-1])
    chord = (1 - w) * a.u[:-1] + w * b_u[:-1]
    x = _on_bound(problem, chord, bound, opts.tol)
    # a chord's point outside a thin domain fails at once: from the step's own ends, both on the
    # curve, a solution within the step's length of the chord is the curve's at the bound
    reach = float(np.linalg.norm(b_u - a.u))
    for start in (b_u[:-1], a.u[:-1]) if x is None else ():
        found = _on_bound(problem, start, bound, opts.tol)
        if found is not None and np.linalg.norm(found - chord) <= reach:
            x = found
            break
    if x is None:
        x = chord  # a fold on the bound: keep the interpolated point
        if not in_domain(problem, np.append(x, bound)):
            # the domain's edge lies before the bound: the curve up to the bound is not known
            edge = capabilities(problem).edge_name_near(a.u)
            mark_end(a, EDGE, f"{EDGE}: {edge} before the {bound_message(bound, opts)}", (a.u[-1], bound))
            a.edge = edge
            return EDGE
    u = np.append(x, bound)
    points.append(
        make_point(
            problem,
            u,
            a.t,
            kind=END,
            message=bound_message(bound, opts),
            bracket=(a.u[-1], b_u[-1]),
            reason=BOUND,
        )
    )
    return BOUND


def _on_bound(problem, x0, bound, tol):
    """Newton at p = bound from x0: the solution, or None."""
    try:
        return newton(problem, x0, bound, tol=tol)
    except (ConvergenceError, np.linalg.LinAlgError):
        return None


def mark_end(point: Point, reason: str, message: str, bracket=None):
    point.kind, point.message, point.reason = END, message, reason
    if bracket is not None:
        point.bracket = bracket


def end_after_failures(problem, points, h, edge_hits, opts):
    """The end after the step fell below its minimum: at the domain's edge (the problem's exact
    edge point when it offers one) if the failures left the domain, else a stall."""
    a = points[-1]
    caps = capabilities(problem)
    named_edge = at_named_edge(caps, a)
    reason = EDGE if edge_hits or named_edge else STALL
    bracket = (a.u[-1], (a.u + 2 * h * a.t)[-1])
    edge = edge_point(problem, a, opts) if reason == EDGE else None
    if edge is not None:
        points.append(
            Point(
                edge,
                a.t,
                0,
                END,
                f"{reason}: {caps.edge_name}",
                bracket,
                a.tests,
                reason=reason,
                edge=caps.edge_name,
            )
        )
    else:
        near = caps.edge_name_near(a.u) if reason == EDGE else "boundary"
        name = near if (named_edge or reason == EDGE) and near != "boundary" else None
        mark_end(a, reason, f"{reason}: {name + ', ' if name else ''}last step {2 * h:.3g} failed", bracket)
        if reason == EDGE:
            a.edge = near
    return reason


def at_named_edge(caps, a: Point) -> bool:
    """A stall right at the edge is the edge: derivatives with a square root there (kappa(A) of
    (39) at the manifold's end) make the corrector fail before the domain check does."""
    near = caps.edge_distance
    return near is not None and near(a.u[:-1], a.u[-1]) < 1e-5


def stalls(caps, a: Point, edge_hits) -> bool:
    """Whether failed steps from a end the direction as a stall (not at the domain's edge)."""
    return not edge_hits and not at_named_edge(caps, a)


def edge_point(problem, a: Point, opts):
    """The problem's exact edge point near a, if it offers one within the parameter bounds."""
    hook = capabilities(problem).edge_point
    edge = hook(a.u[:-1], a.u[-1]) if hook else None
    if edge is None:
        return None
    u = np.append(edge[0], edge[1])
    return u if opts.p_min <= u[-1] <= opts.p_max and np.all(np.isfinite(u)) else None
