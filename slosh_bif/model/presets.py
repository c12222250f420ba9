"""Parameter sets of the paper's figures 9-15, with their initial conditions.

The paper prints initial conditions in the absolute coordinates ``(u, u', v, v')`` of eq. (5);
the models use ``X = u + eps*v`` and ``w = u - v`` (eq. 6 and eq. 1), so each preset stores both
and converts with :func:`state_from_uv`. Derivatives are read as derivatives in tau.

How each printed caption was read (typos and gaps):

* Fig. 9 prints ``u0 = v0' = 0, u0 = 3, v0 = -0.97``: u0 appears twice. Read as u0 = 0,
  u0' = 3, v0 = -0.97, v0' = 0, the initial condition printed in full for Fig. 10.
  The caption gives neither gamma nor sigma; Section 4.1 says no damping acts besides the impacts
  and (43) carries no detuning, so gamma = 0 and sigma = 0. Abar = 0 (free vibrations).
* Fig. 10, 11, 12, 13 and 15 are complete as printed.
* Fig. 14 gives only the forcing (sigma_bar = 4, eps = 0.05, Abar = 1); the remaining parameters
  are taken from Fig. 13 (the Fig. 10 set with Abar = 1 would do as well: the figure shows
  the forcing alone).
* Fig. 15 is "Fig. 10 plus white noise" with no sigma_bar printed; the sigma_bar = 4 of Fig. 14
  is assumed.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.model.params import Params

__all__ = ["Preset", "PRESETS", "KICKED", "CLASSIFY_TMAX", "get_preset", "state_from_uv", "uv_from_state"]


def state_from_uv(u, u_dot, v, v_dot, eps):
    """Model state ``[X, X', w, w']`` from absolute coordinates: X = u + eps v, w = u - v."""
    return np.array([u + eps * v, u_dot + eps * v_dot, u - v, u_dot - v_dot], dtype=float)


def uv_from_state(state, eps):
    """Inverse of :func:`state_from_uv`: ``[u, u', v, v']`` (vectorised over leading axes)."""
    X, Xd, w, wd = np.moveaxis(np.asarray(state, dtype=float), -1, 0)
    u, ud = (X + eps * w) / (1 + eps), (Xd + eps * wd) / (1 + eps)
    return np.stack([u, ud, u - w, ud - wd], axis=-1)


@dataclasses.dataclass(frozen=True)
class Preset:
    """A figure's parameters, initial condition ``(u0, u0', v0, v0')``, noise and time window."""

    name: str
    params: Params
    uv0: tuple
    t_window: tuple
    noise_std: float = 0.0
    note: str = ""

    @property
    def state0(self) -> np.ndarray:
        """Initial state ``[X, X', w, w']``."""
        return state_from_uv(*self.uv0, eps=self.params.eps)

    def state_for(self, params: Params) -> np.ndarray:
        """The figure's initial condition as a state of the model at ``params``: X = u + eps v
        depends on eps, so a changed eps (``--set eps=...``) changes the state, not the motion."""
        return state_from_uv(*self.uv0, eps=params.eps)


_WALL = dict(eps=0.05, lam=0.35, chi=0.2, pbar=0)
KICKED = (0.0, 3.0, -0.97, 0.0)  # u0 = 0, u0' = 3, v0 = -0.97, v0' = 0: the start of Figs. 9, 10, 13-15
_AT_REST = (0.0, 0.0, -0.97, 0.0)  # u0 = 0, u0' = 0, v0 = -0.97, v0' = 0


def _preset(name, uv0, t_window, noise_std=0.0, note="", **params):
    return Preset(name, Params(**{**_WALL, **params}), uv0, t_window, noise_std, note)


PRESETS = {
    p.name: p
    for p in [
        _preset(
            "fig9a",
            KICKED,
            (0, 600),
            n=50,
            beta=0.0,
            gamma=0.0,
            sigma=0.0,
            Abar=0.0,
            note="free vibrations, beta = 0; gamma and sigma not printed, taken as 0",
        ),
        _preset(
            "fig9b",
            KICKED,
            (0, 600),
            n=50,
            beta=0.3,
            gamma=0.0,
            sigma=0.0,
            Abar=0.0,
            note="free vibrations, beta = 0.3; gamma and sigma not printed, taken as 0",
        ),
        _preset(
            "fig10",
            KICKED,
            (1100, 1200),
            n=50,
            beta=0.0,
            gamma=0.2,
            sigma=1.0,
            Abar=3.0,
            note="resonant periodic response",
        ),
        _preset(
            "fig11a",
            _AT_REST,
            (0, 2000),
            n=6,
            beta=0.0,
            gamma=0.2,
            sigma=1.0,
            Abar=0.01,
            note="non-resonant response, beta = 0",
        ),
        _preset(
            "fig11b",
            _AT_REST,
            (0, 2000),
            n=6,
            beta=0.3,
            gamma=0.2,
            sigma=1.0,
            Abar=0.01,
            note="non-resonant response, beta = 0.3",
        ),
        _preset(
            "fig12",
            _AT_REST,
            (0, 5000),
            n=6,
            beta=0.3,
            gamma=0.2,
            sigma=1.0,
            Abar=0.5,
            note="chaotic strongly modulated response",
        ),
        _preset(
            "fig13",
            KICKED,
            (0, 3000),
            n=50,
            beta=0.3,
            gamma=0.2,
            sigma=1.0,
            Abar=1.0,
            note="transition from strongly modulated to periodic response",
        ),
        _preset(
            "fig14",
            KICKED,
            (0, 200),
            noise_std=4.0,
            n=50,
            beta=0.3,
            gamma=0.2,
            sigma=1.0,
            Abar=1.0,
            note="forcing with white noise; only sigma_bar, eps and Abar printed, rest from Fig. 13",
        ),
        _preset(
            "fig15",
            KICKED,
            (0, 1200),
            noise_std=4.0,
            n=50,
            beta=0.0,
            gamma=0.2,
            sigma=1.0,
            Abar=3.0,
            note="Fig. 10 with white noise; sigma_bar not printed, 4 (Fig. 14) assumed",
        ),
    ]
}


CLASSIFY_TMAX = 600.0
"""End time tau of a simulation whose regime is classified (the second half is classified): about
95 forcing periods, 30 units of the slow time eps tau at eps = 0.05. Every command that classifies
(``regimes``, ``chart --regimes``, ``answer regime``) uses it; ``simulate`` uses the preset's window.
Here beside the figures' windows, so that the command line reads it without loading the simulation."""


def get_preset(name: str) -> Preset:
    """The preset called ``name`` (one of :data:`PRESETS`), with a clear error otherwise."""
    try:
        return PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown preset {name!r}; choose one of {', '.join(PRESETS)}") from None
