"""Measured frequency responses: points (sigma, A) of a response curve, the excitation's detuning
sigma of eq. (7) and the amplitude A of the vessel's first harmonic (the slow flow's amplitude,
eqs. 25, 46), with an optional standard deviation of each amplitude and an optional sweep
direction (``up`` or ``down``: the branch a sweep stays on until it jumps, which the fit explains
by the stable branches, never by averaging them)."""

from __future__ import annotations

import csv
import dataclasses
import math
from pathlib import Path

import numpy as np

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
    try:
        with open(path, newline="") as fh:
            reader = csv.DictReader(fh)
            columns = reader.fieldnames or []
            missing = [c for c in RESPONSE_COLUMNS if c not in columns]
            if missing:
                raise ValueError(
                    f"{path}: a frequency response needs the columns sigma and A (and optionally std, "
                    f"sweep); missing {', '.join(missing)} (has {', '.join(columns) or 'no header'})"
                )
            rows = list(reader)
    except (OSError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: cannot be read as a CSV file of response points ({err})") from None
    numbers = ("sigma", "A") + (("std",) if "std" in columns else ())
    values = {name: [] for name in numbers}
    sweep = []
    for k, row in enumerate(rows, start=2):  # line numbers, the header being line 1
        for name in numbers:
            try:
                value = float(row[name])
            except (TypeError, ValueError):
                raise ValueError(f"{path}, line {k}: {name} must be a number; got {row[name]!r}") from None
            if not math.isfinite(value) or (name != "sigma" and value <= 0):
                allowed = "a finite number" if name == "sigma" else "a positive finite number"
                raise ValueError(f"{path}, line {k}: {name} must be {allowed}; got {row[name]!r}")
            values[name].append(value)
        direction = (row.get("sweep") or "").strip().lower()
        if direction not in SWEEPS:
            raise ValueError(f"{path}, line {k}: sweep must be up, down or empty; got {row['sweep']!r}")
        sweep.append(direction)
    if not rows:
        raise ValueError(f"{path}: no response points below the header")
    std = np.array(values["std"]) if "std" in values else None
    return ResponseData(np.array(values["sigma"]), np.array(values["A"]), std, tuple(sweep), str(path))
