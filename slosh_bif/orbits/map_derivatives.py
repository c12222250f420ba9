"""Second and third derivatives of the stroboscopic map of the smooth model (9) (the state after a
time t1 as a function of the state at tau = 0), from its second- and third-order variational
equations along given directions, and the normal-form coefficient of an orbit's bifurcation
(:mod:`slosh_bif.continuation.normal_forms`): LP, PD and NS on the map over the orbit's period,
the symmetry-breaking BP of a symmetric orbit as the flip of its half-period map G = -phi_pi.

Along a solution y(tau) with J = f_y, the derivatives of the flow in directions u, v, w solve

    (Phi u)' = J Phi u,
    W_uv' = J W_uv + f_yy[Phi u, Phi v],
    Z' = J Z + f_yy[Phi u, W_vw] + f_yy[Phi v, W_uw] + f_yy[Phi w, W_uv] + f_yyy[Phi u, Phi v, Phi w],

from Phi u = u, W = Z = 0: W_uv(t1) = D^2 phi[u, v], Z(t1) = D^3 phi[u, v, w], contracted from the
entries of f's second and third derivatives that the sympy derivation writes (the wall terms
chi w^(2n+1) and lam w' w^(2p) of (9)). Complex directions (a Neimark-Sacker point's eigenvector)
are expanded by multilinearity into real ones, and everything one derivative needs (a Neimark-Sacker
coefficient's C(q, q, conj q): four real triples and three pairs) is one integration of the
compiled DOP853 around one kernel for any directions (:mod:`slosh_bif.flows.smooth.variations`);
scipy's DOP853 on the same kernel is the fallback.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from slosh_bif.continuation.normal_forms import flip_coefficient, fold_coefficient, neimark_sacker_coefficient
from slosh_bif.flows.smooth.integrator import integrate_variations
from slosh_bif.model.params import Params

__all__ = [
    "MapDerivatives",
    "FlowDerivatives",
    "criticality",
    "crossing_rate",
    "settle",
    "RTOL",
    "ATOL",
    "COARSE_RTOL",
    "FINE_RTOL",
    "SETTLED",
]

RTOL, ATOL = 1e-11, 1e-13
COARSE_RTOL = 1e-9  # the estimate of a coefficient's error: the coefficient at this tolerance too
FINE_RTOL = 1e-12  # where a coefficient has not settled at RTOL
SETTLED = 0.25  # two tolerances' coefficients this close (relative): its sign is no integration error


class MapDerivatives:
    """A map's derivatives in its initial state y0 (the flow from tau = 0 to ``t1``, times ``sign``
    (-1: the half-period map -phi)): :meth:`jacobian`, :meth:`second` D^2 phi[u, v] and
    :meth:`third` D^3 phi[u, v, w] for real or complex directions, complex ones by multilinearity
    from real parts kept by their directions. A model gives ``jacobian`` and ``_fill``, which
    computes the real pairs and triples asked for together."""

    exact = False  # integrated to ``rtol``: a result's error is seen by integrating more tightly

    @staticmethod
    def key(*directions):
        """A real pair's or triple's cache key (the forms are symmetric: any order)."""
        return _key(*directions)

    def __init__(
        self, params: Params, y0, t1: float, *, sign: float = 1.0, rtol=RTOL, atol=ATOL, backend="auto"
    ):
        self.params, self.y0, self.t1, self.sign = params, np.asarray(y0, dtype=float), float(t1), sign
        self.rtol, self.atol, self.backend = rtol, atol, backend
        self._seconds, self._thirds = {}, {}

    def jacobian(self) -> np.ndarray:
        """d phi(t1) / d y0 (times ``sign``)."""
        raise NotImplementedError

    def _fill(self, pairs, triples):
        """Compute D2 phi of every real pair and D3 phi of every real triple given (each a tuple of
        directions) into ``self._seconds`` and ``self._thirds`` under :meth:`key`."""
        raise NotImplementedError

    def _need(self, pairs=(), triples=()):
        pairs = {key: pair for pair in pairs if (key := _key(*pair)) not in self._seconds}
        triples = {key: triple for triple in triples if (key := _key(*triple)) not in self._thirds}
        if pairs or triples:
            self._fill(list(pairs.values()), list(triples.values()))

    def second(self, u, v):
        """D^2 phi[u, v] (times ``sign``); complex u, v by bilinearity."""
        self._need(pairs=_real_combinations((u, v)))
        return self.sign * _multilinear(lambda a, b: self._seconds[_key(a, b)], (u, v))

    def third(self, u, v, w):
        """D^3 phi[u, v, w] (times ``sign``); complex directions by trilinearity (every real triple
        they need, and the pairs among their parts, computed together)."""
        parts = _real_combinations((u, v, w))
        self._need(pairs=[pair for a, b, c in parts for pair in ((a, b), (a, c), (b, c))], triples=parts)
        return self.sign * _multilinear(lambda a, b, c: self._thirds[_key(a, b, c)], (u, v, w))


class FlowDerivatives(MapDerivatives):
    """The flow of (9) from ``y0`` at tau = 0 to ``t1`` and its derivatives in the initial state,
    from its variational equations (:mod:`slosh_bif.flows.smooth.variations`): everything one
    :meth:`second` or :meth:`third` asks for (every real pair and triple of its directions' parts)
    in one integration. Integrated by the compiled DOP853 (``backend="scipy"``: scipy's, the tested
    fallback)."""

    def jacobian(self) -> np.ndarray:
        """d phi(t1) / d y0 (times ``sign``): the first variational equations along the unit vectors."""
        end = integrate_variations(
            self.params, self.y0, self.t1, np.eye(4), rtol=self.rtol, atol=self.atol, backend=self.backend
        )
        return self.sign * end[4:20].reshape(4, 4).T

    def _fill(self, pairs, triples):
        """One integration: the directions of ``pairs`` and ``triples``, every pair asked for or
        inside a triple, every triple."""
        directions = {d.tobytes(): d for group in (*pairs, *triples) for d in group}
        index = {key: k for k, key in enumerate(directions)}
        inside = [pair for a, b, c in triples for pair in ((b, c), (a, c), (a, b))]
        pairs = list({_key(*pair): pair for pair in (*pairs, *inside)}.values())
        end = integrate_variations(
            self.params,
            self.y0,
            self.t1,
            list(directions.values()),
            [tuple(index[d.tobytes()] for d in pair) for pair in pairs],
            [tuple(index[d.tobytes()] for d in triple) for triple in triples],
            rtol=self.rtol,
            atol=self.atol,
            backend=self.backend,
        )
        at = 4 + 4 * len(directions)
        for k, pair in enumerate(pairs):
            self._seconds[_key(*pair)] = end[at + 4 * k : at + 4 * k + 4]
        at += 4 * len(pairs)
        for k, triple in enumerate(triples):
            self._thirds[_key(*triple)] = end[at + 4 * k : at + 4 * k + 4]


def _key(*directions):
    """A symmetric multilinear form's cache key: its directions' bytes in sorted order."""
    return tuple(sorted(np.asarray(d, dtype=float).tobytes() for d in directions))


def _signed(v, factor):
    """(v, factor) with v's first non-zero entry positive (the sign moved into the factor)."""
    v = np.asarray(v, dtype=float)
    nonzero = np.flatnonzero(v)
    return (-v, -factor) if nonzero.size and v[nonzero[0]] < 0 else (v, factor)


def _parts(a) -> list:
    """[(real direction, factor)] of a vector: its real part, and its imaginary part with factor i."""
    return [_signed(np.real(a), 1.0 + 0j)] + (
        [_signed(np.imag(a), 1j)] if np.iscomplexobj(a) and np.any(np.imag(a)) else []
    )


def _real_combinations(args) -> list:
    """Every tuple of real directions (one part of each argument) that a multilinear form at the
    complex ``args`` needs."""
    return [tuple(combo) for combo in itertools.product(*[[d for d, _ in _parts(a)] for a in args])]


def _multilinear(real_fn, args):
    """A real multilinear function of real vectors, evaluated at complex ones: each argument split
    into its real and imaginary parts (the products of i's collected), each part's sign moved
    into its factor so that q and conj(q) ask for the same real directions."""
    parts = [_parts(a) for a in args]
    total = 0.0 + 0j
    for combo in np.ndindex(*[len(p) for p in parts]):
        vectors = [parts[k][j][0] for k, j in enumerate(combo)]
        factor = math.prod(parts[k][j][1] for k, j in enumerate(combo))
        total = total + factor * real_fn(*vectors)
    return total if np.iscomplexobj(total) and np.any(np.imag(total)) else np.real(total)


def _map_of(kind, period):
    """(t1, sign) of the map a ``kind`` point is judged on: G = -phi_(period / 2) at a BP."""
    return (period / 2, -1.0) if kind == "BP" else (period, 1.0)


def crossing_rate(
    params_at, p0: float, y0, dy, kind: str, nf, *, period=2 * math.pi, h=1e-5, derivatives=FlowDerivatives
) -> float:
    """d beta / dp at the ``kind`` point ``nf`` (its q and adjoint p) of the orbit through ``y0`` at
    the parameter value ``p0`` (``params_at(p)`` gives the set): beta = -mu - 1 at a flip (a PD, or
    a BP as the flip of G), |mu| - 1 at a Neimark-Sacker point, with d mu / dp = <p, (D^2 phi[., dy]
    + d_p D phi) q> along the branch (``dy`` = d y0 / dp, from its tangent; d_p D phi by a central
    difference of the exact Jacobian in the parameter, step ``h`` relative). ``derivatives``: the
    model's map derivatives (:class:`FlowDerivatives` for (9), or one with its signature)."""
    t1, sign = _map_of(kind, period)
    step = h * max(1.0, abs(p0))
    flow = derivatives(params_at(p0), y0, t1, sign=sign)
    dA = (
        derivatives(params_at(p0 + step), y0, t1, sign=sign).jacobian()
        - derivatives(params_at(p0 - step), y0, t1, sign=sign).jacobian()
    ) / (2 * step)
    q, p = nf.q, nf.p
    mu = np.vdot(p, flow.jacobian() @ q)
    dmu = np.vdot(p, flow.second(q, np.asarray(dy, dtype=float)) + dA @ q)
    if nf.kind == "PD":
        return float(-dmu.real)
    return float((np.conj(mu) * dmu).real / abs(mu))


def criticality(
    params: Params,
    y0,
    kind: str,
    *,
    period: float = 2 * math.pi,
    symmetric: bool = False,
    rtol: float = RTOL,
    jacobian=None,
    derivatives=FlowDerivatives,
):
    """The :class:`~slosh_bif.continuation.normal_forms.NormalForm` of the orbit of (9) through
    ``y0`` (at tau = 0) at a ``kind`` point: LP, PD or NS of the map over ``period``; BP (a
    symmetric orbit's pitchfork) as the flip of the half-period map G = -phi_(period / 2). ``rtol``:
    the variational equations' relative tolerance (``atol`` a hundredth of it); ``jacobian``: the
    map's Jacobian where the caller has it (a curve's arcs), else integrated here; ``derivatives``:
    the class of the model's map derivatives (:class:`FlowDerivatives` for (9), or one with its
    signature, such as (8)'s)."""
    if kind == "BP" and not symmetric:
        raise ValueError("the pitchfork's coefficient is that of a symmetric orbit's half-period map")
    t1, sign = _map_of(kind, period)
    flow = derivatives(params, y0, t1, sign=sign, rtol=rtol, atol=rtol * 1e-2)
    A = flow.jacobian() if jacobian is None else np.asarray(jacobian, dtype=float)
    if kind in ("PD", "BP"):
        return flip_coefficient(A, flow.second, flow.third)
    if kind == "LP":
        return fold_coefficient(A, flow.second)
    if kind == "NS":
        return neimark_sacker_coefficient(A, flow.second, flow.third)
    raise ValueError(f"kind must be LP, PD, NS or BP; got {kind!r}")


def settle(evaluate, nf, *, exact: bool = False):
    """(NormalForm or None, whether its coefficient has settled) from ``nf = evaluate(RTOL)``:
    ``evaluate(rtol)`` is the normal form with the map's derivatives integrated at ``rtol`` (None
    where they cannot be). ``nf`` is kept where the one at :data:`COARSE_RTOL` agrees with it
    within :data:`SETTLED`; else the one at :data:`FINE_RTOL` is kept, settled where it agrees with
    ``nf``. Where the map's derivatives are stiff (a high-power wall) the coefficient is a small
    difference of large terms, and its sign at one tolerance can be the integration's error.
    ``exact`` derivatives (not integrated: (8)'s jets) are taken as they are."""
    if nf is None or exact:
        return nf, True
    coarse = evaluate(COARSE_RTOL)
    if coarse is not None and _agree(coarse.coefficient, nf.coefficient):
        return nf, True
    fine = evaluate(FINE_RTOL)
    if fine is None:
        return nf, False
    return fine, _agree(nf.coefficient, fine.coefficient)


def _agree(rough, better) -> bool:
    return bool(abs(rough - better) <= SETTLED * abs(better))
