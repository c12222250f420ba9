"""What the compiled DOP853 loops of (9) take and return, without numba: the Butcher tableau, the
kernel numbers of the switch (``WHICH``: (9), (9) with its variational equations for shooting,
(9) with the random forcing of (47), the pair kernel for any two parameters, the variational
equations of first to third order along any directions, the pair kernel with its derivatives along
a direction of the start state), the status codes
with their messages. The loops themselves (:mod:`slosh_bif.flows.smooth.dop853`) are compiled by numba
and loaded at the first integration (:mod:`slosh_bif.flows.loops`); :mod:`slosh_bif.flows.smooth.integrator`
calls them with these.
"""

from __future__ import annotations

import numpy as np

from slosh_bif.model._generated import dop853_tableau as _dop

__all__ = [
    "STAGES",
    "TABLEAU",
    "WHICH",
    "OK",
    "MESSAGES",
    "SHOOTING_SIZE",
    "ALONG_SIZE",
    "EXTRA_SIZE",
    "TAPE_WIDTH",
    "MODEL_PARAMETERS",
    "variation_parameters",
    "variations_size",
]

STAGES = _dop.N_STAGES
# A, B, C, E3, E5 (scipy's DOP853 coefficients, written by the derivation); every loop takes them last.
TABLEAU = tuple(np.array(v) for v in (_dop.A, _dop.B, _dop.C, _dop.E3, _dop.E5))
WHICH = {
    "plain": 0,
    "shooting": 1,
    "noisy": 2,
    "pair": 3,
    "variations": 4,
    "along": 5,
    "along_extra": 6,
    "along_sigma_abar": 7,
}
SHOOTING_SIZE = 29  # [y, Phi, dy/dp1, dy/dp2, int tr J]
ALONG_SIZE = 57  # the along kernel: [the shooting system's 29, d, D Phi . d, D dy/da . d, D dy/db . d]
EXTRA_SIZE = ALONG_SIZE - SHOOTING_SIZE  # what the along extra kernels give, replayed on kept steps
TAPE_WIDTH = 2 + 13 * SHOOTING_SIZE  # a kept step: tau, h, the states its 13 stages were evaluated at

# Status codes of the loops.
OK, MAX_STEPS, TOO_SMALL, NOT_FINITE = 0, 1, 2, 3
MESSAGES = {
    OK: "ok",
    MAX_STEPS: "step limit reached",
    TOO_SMALL: "step size fell below the rounding limit",
    NOT_FINITE: "the solution became non-finite",
}

MODEL_PARAMETERS = 9  # (eps, beta, gamma, sigma, Abar, lam, chi, n, p) at the head of every pars


def variations_size(directions: int, pairs: int, triples: int) -> int:
    """The variations kernel's state length for K directions, P pairs and T triples."""
    return 4 * (1 + directions + pairs + triples)


def variation_parameters(model_pars, directions: int, pairs, triples) -> np.ndarray:
    """The variations kernel's ``pars``: ``model_pars`` (the nine of (9)), K = ``directions``, the pairs
    [(a, b)] and the triples [(a, b, c)] as indices of the directions; a triple's three pairs must
    be among ``pairs`` (ValueError otherwise)."""
    pairs = [tuple(sorted(pair)) for pair in pairs]
    rows = []
    for a, b, c in triples:
        try:
            rows += [a, b, c, *(pairs.index(tuple(sorted(pair))) for pair in ((b, c), (a, c), (a, b)))]
        except ValueError:
            raise ValueError(f"the triple {(a, b, c)} needs its three pairs among the pairs") from None
    model = np.asarray(model_pars, dtype=float)[:MODEL_PARAMETERS]
    return np.concatenate([model, [directions, len(pairs), len(triples)], np.ravel(pairs), rows])
