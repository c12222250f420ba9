"""The first-, second- and third-order variational equations of (9) along any real directions of
the start state, in one kernel of the compiled DOP853 loop: what the normal-form coefficients of
an orbit's bifurcations need (:mod:`slosh_bif.orbits.map_derivatives`), all from one integration.

Along y(tau) with J = f_y, for directions a, b, c of the start state,

    (Phi a)' = J Phi a,
    W_ab' = J W_ab + f_yy[Phi a, Phi b],
    Z_abc' = J Z_abc + f_yy[Phi a, W_bc] + f_yy[Phi b, W_ac] + f_yy[Phi c, W_ab] + f_yyy[Phi a, Phi b, Phi c],

from Phi a = a, W = Z = 0: W_ab(t1) = D^2 phi[a, b], Z_abc(t1) = D^3 phi[a, b, c]. The contractions
come from the non-zero entries of f's second and third derivatives that the sympy derivation
writes (``smooth_jet_kernel``: f, J and those entries at (tau, y); for (9) the wall terms
chi w^(2n+1) and lam w' w^(2p) give three and four), so one kernel serves any set of directions,
pairs and triples: the state is [y, Phi d_0 .. Phi d_(K-1), W_0 .. W_(P-1), Z_0 .. Z_(T-1)], four
numbers each, and the kernel's ``pars``
(:func:`~slosh_bif.flows.smooth.dop853_interface.variation_parameters`) carry after the model's
nine the counts K, P, T and each pair's directions and each triple's directions with its three
pairs.
"""

from __future__ import annotations

from slosh_bif.flows.compiled import jit as _jit
from slosh_bif.flows.smooth.dop853_interface import MODEL_PARAMETERS as _MODEL
from slosh_bif.model._generated import kernels as _kernels

__all__ = ["variations_kernel"]

_SECOND = _kernels.SMOOTH_SECOND_ENTRIES
_THIRD = _kernels.SMOOTH_THIRD_ENTRIES
_H0 = 20  # the jet: f (4), J (16), then the second derivative's entries, then the third's
_T0 = _H0 + len(_SECOND)
_jet = _jit(_kernels.smooth_jet_kernel, inline=True)


def variations_kernel(tau, z, out, pars):
    """out = d/dtau of the state above (see the module's docstring)."""
    jet = _jet(tau, z, pars)
    k_dirs, n_pairs, n_triples = int(pars[_MODEL]), int(pars[_MODEL + 1]), int(pars[_MODEL + 2])
    for i in range(4):
        out[i] = jet[i]
    for block in range(4, 4 * (1 + k_dirs + n_pairs + n_triples), 4):  # J times every vector
        for i in range(4):
            total = 0.0
            for j in range(4):
                total += jet[4 + 4 * i + j] * z[block + j]
            out[block + i] = total
    pair_at, pairs = 4 + 4 * k_dirs, _MODEL + 3
    for k in range(n_pairs):  # + f_yy[Phi a, Phi b]
        a, b = 4 + 4 * int(pars[pairs + 2 * k]), 4 + 4 * int(pars[pairs + 2 * k + 1])
        for e in range(len(_SECOND)):
            i, j, m = _SECOND[e]
            out[pair_at + 4 * k + i] += jet[_H0 + e] * z[a + j] * z[b + m]
    triple_at, triples = pair_at + 4 * n_pairs, pairs + 2 * n_pairs
    for k in range(n_triples):
        row = triples + 6 * k
        a, b, c = 4 + 4 * int(pars[row]), 4 + 4 * int(pars[row + 1]), 4 + 4 * int(pars[row + 2])
        bc, ac, ab = (
            pair_at + 4 * int(pars[row + 3]),
            pair_at + 4 * int(pars[row + 4]),
            pair_at + 4 * int(pars[row + 5]),
        )
        at = triple_at + 4 * k
        for e in range(len(_SECOND)):  # + f_yy[Phi a, W_bc] + f_yy[Phi b, W_ac] + f_yy[Phi c, W_ab]
            i, j, m = _SECOND[e]
            out[at + i] += jet[_H0 + e] * (z[a + j] * z[bc + m] + z[b + j] * z[ac + m] + z[c + j] * z[ab + m])
        for e in range(len(_THIRD)):  # + f_yyy[Phi a, Phi b, Phi c]
            i, j, m, r = _THIRD[e]
            out[at + i] += jet[_T0 + e] * z[a + j] * z[b + m] * z[c + r]
