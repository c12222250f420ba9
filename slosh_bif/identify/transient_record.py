"""A record in time from a known start, X(tau) of the vessel released from rest (a free decay, or a
forced transient at the set's sigma and Abar), and the trajectory of the full model it is compared
with: of the smooth model (9) or of the vibro-impact model (8) (eqs. 8, 9, 39), from the state
(X0, 0, 0, 0) at the record's first time (the vessel at X0 at rest, the liquid at rest in the
middle), X0 fitted with the parameters.

Data: a CSV with ``tau`` and ``X`` (optionally ``std``), tau strictly increasing (the forcing's
phase of eq. (7) when forced). The samples' derivatives are the models' own: (9)'s variational
equations from Phi = I (the column of X0) and zero parameter sensitivities at the start; (8)'s
saltation sensitivities at every sample and impact, carried to the record's times by the flight's
closed form (:class:`~.impact_samples.Flights`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.flows.impact.propagators import LINEAR_PARAMETERS, WALL_PARAMETERS
from slosh_bif.flows.smooth import integrator
from slosh_bif.identify.csv_table import read_columns
from slosh_bif.identify.impact_samples import Flights
from slosh_bif.identify.response_impact import STEP
from slosh_bif.model.params import REAL_FIELDS, Params

__all__ = [
    "TransientRecord",
    "read_transient_record",
    "Trajectory",
    "TRANSIENT_MODELS",
    "TRAJECTORY_NAMES",
    "MIN_SAMPLES",
]

TRANSIENT_MODELS = ("smooth", "impact", "impact-corrected")
TRAJECTORY_NAMES = {
    "smooth": "the trajectory of the smooth model (9)",
    "impact": "the trajectory of the vibro-impact model (8)",
    "impact-corrected": "the trajectory of the corrected impact model",
}
MIN_SAMPLES = 10  # a record's samples at least
TOL = 1e-10  # the integration's tolerance for (9)'s samples
MAX_IMPACTS = 100_000  # impacts in one run of (8) at most (a run that needs more is said to fail)


@dataclasses.dataclass(frozen=True)
class TransientRecord:
    """A record from a known start: times ``tau``, displacements ``X``, optional ``std``, the file."""

    tau: np.ndarray
    X: np.ndarray
    std: np.ndarray | None = None
    source: str = ""

    def __len__(self) -> int:
        return len(self.tau)

    @property
    def A(self) -> np.ndarray:
        """The measured values (the name the fits' shared code reads)."""
        return self.X

    def head(self, count: int) -> TransientRecord:
        """The record's first ``count`` samples."""
        std = None if self.std is None else self.std[:count]
        return TransientRecord(self.tau[:count], self.X[:count], std, self.source)


def read_transient_record(path) -> TransientRecord:
    """``tau, X[, std]``; one-line errors naming the file, line and column: tau strictly
    increasing over at least :data:`MIN_SAMPLES` rows, std positive."""
    path = Path(path)
    values = read_columns(path, ("tau", "X"), "a record in time", optional=("std",))
    tau = values["tau"]
    if len(tau) < MIN_SAMPLES or np.any(np.diff(tau) <= 0):
        raise ValueError(f"{path}: tau must increase strictly over at least {MIN_SAMPLES} rows")
    return TransientRecord(tau, values["X"], values.get("std"), str(path))


class Trajectory:
    """X of ``model`` ("smooth": (9); "impact": (8); "impact-corrected") at a record's times from
    the state (X0, 0, 0, 0) at the first, and its derivatives in the parameters and X0."""

    def __init__(self, model: str = "smooth"):
        if model not in TRANSIENT_MODELS:
            raise ValueError(
                f"a record from a known start is compared with {', '.join(TRANSIENT_MODELS)}; got {model!r}"
            )
        self.model = model

    def differentiates(self, names) -> bool:
        """Whether :meth:`derivatives` has every name (the corrected impact model has no
        derivatives in the wall's lam and chi)."""
        if self.model == "smooth":
            return all(name in REAL_FIELDS for name in names)
        allowed = LINEAR_PARAMETERS + (WALL_PARAMETERS if self.model == "impact" else ())
        return all(name in allowed for name in names)

    def values(self, params: Params, X0: float, tau) -> np.ndarray:
        """X at ``tau`` (tau[0] the start). RuntimeError where a run fails."""
        tau = np.asarray(tau, dtype=float)
        y0 = np.array([X0, 0.0, 0.0, 0.0])
        if self.model == "smooth":
            return integrator.integrate_grid(params, y0, tau, rtol=TOL, atol=TOL * 1e-2)[:, 0]
        flow = ImpactFlow(params, STEP, variant=self._variant)
        t, y, _, _, _, code = flow.sensitivities(y0, tau[0], tau[-1] - tau[0], max_impacts=MAX_IMPACTS)
        _check(code, tau)
        return Flights(flow, t, y, tau).X()

    def derivatives(self, params: Params, X0: float, tau, names) -> tuple:
        """(X, dX/d(names..., X0)) at ``tau``: the last column X0's. RuntimeError where a run fails."""
        tau = np.asarray(tau, dtype=float)
        y0 = np.array([X0, 0.0, 0.0, 0.0])
        if self.model == "smooth":
            return _smooth(params, y0, tau, names)
        return _impact(params, y0, tau, names, self._variant)

    @property
    def _variant(self) -> str:
        return "corrected" if self.model == "impact-corrected" else "paper"


def _check(code: int, tau) -> None:
    if code != 0:
        raise RuntimeError(f"the run of (8) from tau = {tau[0]:.4g} ends early (code {code})")


def _smooth(params: Params, y0, tau, names) -> tuple:
    """(9) and its variational equations on the record's times: Phi[:, 0, 0] is X0's column."""
    rows = [[1.0 if field == name else 0.0 for field in REAL_FIELDS] for name in names]
    pad = len(rows) % 2 if rows else 2  # the kernel takes directions in pairs; X0's column needs a run
    rows += [[0.0] * len(REAL_FIELDS)] * pad
    columns, X, Phi = [], None, None
    for k in range(0, len(rows), 2):
        z = integrator.integrate_grid(params, y0, tau, rtol=TOL, atol=TOL * 1e-2, directions=rows[k : k + 2])
        X, Phi = z[:, 0], z[:, 4:20].reshape(-1, 4, 4)
        columns.append(z[:, 20:28].reshape(-1, 2, 4)[:, :, 0])
    dX = np.concatenate(columns, axis=1)[:, : len(names)]
    return X, np.column_stack([dX, Phi[:, 0, 0]])


def _impact(params: Params, y0, tau, names, variant: str) -> tuple:
    """(8)'s exact flow with its saltation sensitivities, one run per name."""
    X, columns = None, []
    for name in [None, *names]:
        flow = ImpactFlow(params, STEP, param=name, variant=variant)
        t, y, phis, dps, _, code = flow.sensitivities(y0, tau[0], tau[-1] - tau[0], max_impacts=MAX_IMPACTS)
        _check(code, tau)
        at = Flights(flow, t, y, tau)
        if name is None:
            X = at.X()
            x0_column = at.derivative(phis[at.last][:, :, 0], parameter=False)
            continue
        columns.append(at.derivative(dps[at.last]))
    return X, np.column_stack([*columns, x0_column])
