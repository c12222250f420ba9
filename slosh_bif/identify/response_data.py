"""Measured frequency responses: points (sigma, A) of a response curve, the excitation's detuning
sigma of eq. (7) and the amplitude A of the vessel's first harmonic (the slow flow's amplitude,
eqs. 25, 46), with an optional standard deviation of each amplitude and an optional sweep
direction (``up`` or ``down``: the branch a sweep stays on until it jumps, which the fit explains
by the stable branches, never by averaging them).

Or in physical units (columns ``f_hz``, ``A_m``, optionally ``std_m``) with a tank parameter file:
each point's excitation frequency f_i is a parameter set of its own, as ``slosh-bif tank`` would
make it at f_i (:func:`~slosh_bif.model.tank.tank_model`, eq. 7 with tau = Omega t): with r_i =
f_ref / f_i (f_ref the file's excitation frequency), ``1 - eps sigma_i = (1 - eps sigma_ref)
r_i**2``, ``gamma_i = gamma r_i`` and ``Abar_i = Abar r_i**4`` (a sweep at constant ground
acceleration); amplitudes are divided by the clearance. A fitted gamma or Abar is then the
value at f_ref."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from slosh_bif.identify.csv_table import number, read_header, read_table
from slosh_bif.model.params import Params
from slosh_bif.model.tank import Site

__all__ = ["ResponseData", "read_response_data", "RESPONSE_COLUMNS", "PHYSICAL_COLUMNS", "SWEEPS"]

RESPONSE_COLUMNS = ("sigma", "A")  # required; "std" and "sweep" optional
PHYSICAL_COLUMNS = ("f_hz", "A_m")  # required with a tank file; "std_m" and "sweep" optional
SWEEPS = ("up", "down", "")


@dataclasses.dataclass(frozen=True)
class ResponseData:
    """Measured response points: ``sigma``, amplitude ``A``, each amplitude's standard deviation
    ``std`` (None: equal, estimated from the residuals), the ``sweep`` direction of each point
    (empty strings where not given), the file they came from and, for data in Hz, each point's
    ``ratio`` f_ref / f_i (None: one parameter set but for sigma)."""

    sigma: np.ndarray
    A: np.ndarray
    std: np.ndarray | None = None
    sweep: tuple = ()
    source: str = ""
    ratio: np.ndarray | None = None
    f_hz: np.ndarray | None = None  # data in Hz: each point's frequency
    clearance: float = 1.0  # data in metres: the length unit

    def sweep_order(self) -> list:
        """(i, previous) for every point in the order a model follows them: points without a
        direction first (previous None), then each sweep's by increasing (up) or decreasing (down)
        sigma, previous the sweep's point before (None for its first)."""
        sweep = self.sweep or ("",) * len(self)
        out = []
        for direction, sign in (("", 1), ("up", 1), ("down", -1)):
            points = sorted(
                (i for i in range(len(self)) if sweep[i] == direction), key=lambda i: sign * self.sigma[i]
            )
            out += [(i, None if direction == "" or k == 0 else points[k - 1]) for k, i in enumerate(points)]
        return out

    def axes(self) -> tuple:
        """(x, amplitude scale, x label, amplitude unit) for a plot in the data's own units."""
        if self.f_hz is None:
            return self.sigma, 1.0, "sigma", ""
        return self.f_hz, self.clearance, "excitation frequency (Hz)", " (m)"

    def __len__(self) -> int:
        return len(self.sigma)

    def params_at(self, base: Params, i: int) -> Params:
        """The parameter set of point i: ``base`` at its sigma (and, for data in Hz, its gamma and
        Abar scaled to its frequency)."""
        if self.ratio is None:
            return base.replace(sigma=float(self.sigma[i]))
        r = float(self.ratio[i])
        return base.replace(sigma=float(self.sigma[i]), gamma=base.gamma * r, Abar=base.Abar * r**4)

    def direction_at(self, i: int, name: str) -> dict:
        """How point i's parameter set moves per unit of the fitted parameter ``name`` (weights over
        the real parameters; the derivative of :meth:`params_at`): data in Hz scale gamma by the
        point's ratio and Abar by its fourth power."""
        if self.ratio is None or name not in ("gamma", "Abar"):
            return {name: 1.0}
        r = float(self.ratio[i])
        return {name: r if name == "gamma" else r**4}


def read_response_data(path, params: Params | None = None, site: Site | None = None) -> ResponseData:
    """The response points of a CSV file with a header holding ``sigma`` and ``A`` (optionally
    ``std`` and ``sweep``), or ``f_hz`` and ``A_m`` (optionally ``std_m``, ``sweep``) with the
    tank's ``site`` and its ``params``; a one-line ValueError naming the file and the line or
    column otherwise, before any fitting."""
    path = Path(path)
    physical = "f_hz" in read_header(path)
    if physical and site is None:
        raise ValueError(
            f"{path}: a response in Hz and metres (f_hz, A_m) needs the tank it was measured on: "
            "--params FILE with a [tank] table (as `slosh-bif tank --out` writes)"
        )
    names = PHYSICAL_COLUMNS if physical else RESPONSE_COLUMNS
    spread = "std_m" if physical else "std"
    what = "a frequency response" + (" in physical units" if physical else "")
    columns, rows = read_table(path, names, what, optional=(spread, "sweep"))
    numbers = names + ((spread,) if spread in columns else ())
    values = {name: [] for name in numbers}
    sweep = []
    for k, row in enumerate(rows, start=2):  # line numbers, the header being line 1
        for name in numbers:
            values[name].append(number(path, k, name, row[name], positive=name != "sigma"))
        direction = (row.get("sweep") or "").strip().lower()
        if direction not in SWEEPS:
            raise ValueError(f"{path}, line {k}: sweep must be up, down or empty; got {row['sweep']!r}")
        sweep.append(direction)
    if not rows:
        raise ValueError(f"{path}: no response points below the header")
    std = np.array(values[spread]) if spread in values else None
    if not physical:
        return ResponseData(np.array(values["sigma"]), np.array(values["A"]), std, tuple(sweep), str(path))
    ratio = site.excitation_frequency / np.array(values["f_hz"])
    sigma = (1.0 - (1.0 - params.eps * params.sigma) * ratio**2) / params.eps
    D = site.clearance
    A = np.array(values["A_m"]) / D
    std = None if std is None else std / D
    return ResponseData(sigma, A, std, tuple(sweep), str(path), ratio, np.array(values["f_hz"]), D)
