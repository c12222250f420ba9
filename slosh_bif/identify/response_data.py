"""Measured frequency responses: points (sigma, A) of a response curve, the excitation's detuning
sigma of eq. (7) and the amplitude A of the vessel's first harmonic (the slow flow's amplitude,
eqs. 25, 46), with an optional standard deviation of each amplitude and an optional sweep
direction (``up`` or ``down``: the branch a sweep stays on until it jumps, which the fit explains
by the stable branches, never by averaging them)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from slosh_bif.identify.csv_table import number, read_table

__all__ = ["ResponseData", "read_response_data", "RESPONSE_COLUMNS", "SWEEPS"]

RESPONSE_COLUMNS = ("sigma", "A")  # required; "std" and "sweep" optional
SWEEPS = ("up", "down", "")


@dataclasses.dataclass(frozen=True)
class ResponseData:
    """Measured response points: ``sigma``, amplitude ``A``, each amplitude's standard deviation
    ``std`` (None: equal, estimated from the residuals), the ``sweep`` direction of each point
    (empty strings where not given) and the file they came from."""

    sigma: np.ndarray
    A: np.ndarray
    std: np.ndarray | None = None
    sweep: tuple = ()
    source: str = ""

    def __len__(self) -> int:
        return len(self.sigma)


def read_response_data(path) -> ResponseData:
    """The response points of a CSV file with a header holding ``sigma`` and ``A`` (optionally
    ``std`` and ``sweep``); a one-line ValueError naming the file and the line or column
    otherwise, before any fitting."""
    path = Path(path)
    columns, rows = read_table(path, RESPONSE_COLUMNS, "a frequency response", optional=("std", "sweep"))
    numbers = ("sigma", "A") + (("std",) if "std" in columns else ())
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
    std = np.array(values["std"]) if "std" in values else None
    return ResponseData(np.array(values["sigma"]), np.array(values["A"]), std, tuple(sweep), str(path))
