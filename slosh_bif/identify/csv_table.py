"""Measured data as CSV tables with a header: the one reader of :mod:`.response_data` and
:mod:`.impact_records`, whose errors name the file, the line and the column, before any fitting."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

__all__ = ["read_header", "read_table", "number", "read_columns"]


def read_header(path) -> list:
    """The column names on the first line of the CSV file ``path`` (a one-line ValueError when it
    cannot be read)."""
    try:
        with open(path, newline="") as fh:
            return next(csv.reader(fh), [])
    except (OSError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: cannot be read as a CSV file ({err})") from None


def read_table(path, required, what: str, optional=()) -> tuple:
    """(columns, rows as dicts) of the CSV file ``path``; a one-line ValueError when it cannot be
    read or lacks one of the ``required`` columns (``what``: what the file should hold)."""
    path = Path(path)
    try:
        with open(path, newline="") as fh:
            reader = csv.DictReader(fh)
            columns = reader.fieldnames or []
            missing = [c for c in required if c not in columns]
            if missing:
                extra = f" (and optionally {', '.join(optional)})" if optional else ""
                raise ValueError(
                    f"{path}: needs the columns {' and '.join(required)}{extra} for {what}; missing "
                    f"{', '.join(missing)} (has {', '.join(columns) or 'no header'})"
                )
            return columns, list(reader)
    except (OSError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: cannot be read as a CSV file of {what} ({err})") from None


def number(path, line: int, name: str, text, *, positive: bool) -> float:
    """The cell ``text`` of column ``name`` on ``line`` as a finite (``positive``: and positive)
    number, or a one-line ValueError naming the file, the line and the column."""
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise ValueError(f"{path}, line {line}: {name} must be a number; got {text!r}") from None
    if not math.isfinite(value) or (positive and value <= 0):
        allowed = "a positive finite number" if positive else "a finite number"
        raise ValueError(f"{path}, line {line}: {name} must be {allowed}; got {text!r}")
    return value


def read_columns(path, required, what: str, optional=()) -> dict:
    """The ``required`` and present ``optional`` columns of ``path`` as float arrays (``std``
    positive), through :func:`read_table` and :func:`number`: one-line errors naming the cell."""
    columns, rows = read_table(path, required, what, optional=optional)
    names = tuple(required) + tuple(name for name in optional if name in columns)
    values = {name: [] for name in names}
    for k, row in enumerate(rows, start=2):
        for name in names:
            values[name].append(number(path, k, name, row[name], positive=name == "std"))
    return {name: np.array(column, dtype=float) for name, column in values.items()}
