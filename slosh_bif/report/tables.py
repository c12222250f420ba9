"""One CSV writer for the tables every command writes (frc, critical, branch, compare, regimes)."""

from __future__ import annotations

import csv
from pathlib import Path

from slosh_bif.report.files import replaced_atomically

__all__ = ["write_rows"]


def write_rows(rows, columns, path, *, digits: int = 12) -> Path:
    """Write dict ``rows`` with a header of ``columns``; floats with ``digits`` significant digits.
    The file appears complete or not at all (:func:`~slosh_bif.report.files.replaced_atomically`)."""
    path = Path(path)
    with replaced_atomically(path) as tmp, open(tmp, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow(
                {k: (f"{row[k]:.{digits}g}" if isinstance(row[k], float) else row[k]) for k in columns}
            )
    return path
