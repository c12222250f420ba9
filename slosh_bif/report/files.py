"""The stores that long runs resume from (settings checked before anything is reused; damaged
ones refused in one line), written whole or not at all by :mod:`slosh_bif.atomic`."""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

from slosh_bif.atomic import replaced_atomically, write_text_atomically

__all__ = [
    "Resume",
    "replaced_atomically",
    "write_text_atomically",
    "read_store",
    "check_settings",
    "pickle_store",
    "CellStore",
    "damaged",
]

# What reading a damaged store can raise: bad JSON or pickle, missing keys, wrong types, a cut zip.
DAMAGE = (ValueError, KeyError, TypeError, IndexError, AttributeError, EOFError, OSError)


@dataclasses.dataclass(frozen=True)
class Resume:
    """A long run's pieces (a scan's starts, a chart's curves, a sweep's cells) kept as they finish
    and reused.

    Attributes
    ----------
    done :
        What an earlier run with the same settings finished (its form is the run's: a scan's
        ``(k, branches)``, a chart's ``{start index: curve}``, a sweep's ``{cell: result}``); None for a fresh
        run.
    keep :
        ``keep(k, piece)``, called as each piece finishes (to store it), or None.
    """

    done: object = None
    keep: object = None


def damaged(path, err) -> ValueError:
    """The one-line error for a store that --resume cannot use."""
    return ValueError(
        f"--resume: {path} is damaged or not this program's store ({type(err).__name__}: {err}); "
        "run without --resume or into another --out"
    )


def read_store(path, settings: dict, *, key: str | None = "settings") -> dict:
    """The JSON that an earlier run stored in ``path``, when its settings (``stored[key]``, or
    the whole file when ``key`` is None) equal ``settings``; else a one-line ValueError naming
    the settings that differ (what ``--resume`` needs before reusing anything)."""
    try:
        stored = json.loads(Path(path).read_text())
    except (OSError, ValueError) as err:
        raise ValueError(f"--resume: cannot read {path}: {err}") from None
    if not isinstance(stored, dict) or not isinstance(stored if key is None else stored.get(key, {}), dict):
        raise damaged(path, TypeError("not a JSON object of settings"))
    check_settings(path, stored if key is None else stored.get(key, {}), settings)
    return stored


def check_settings(path, found: dict, settings: dict) -> None:
    """A one-line ValueError naming the settings that differ between a store and this run."""
    if found != settings:
        differ = sorted(k for k in settings if found.get(k) != settings[k])
        raise ValueError(
            f"--resume: {path} was written for other settings ({', '.join(differ)} differ); run "
            "without --resume or into another --out"
        )


def pickle_store(path, settings: dict, *, resume: bool):
    """(done, keep) for a run whose partial results are Python objects (a scan's traced
    branches): ``done`` the object an earlier run with the same ``settings`` stored in ``path``
    (resume; else None), ``keep(*state)`` stores ``state``, atomically. Pickle: the objects are
    this package's own, written and read by the same user's runs."""
    import pickle

    path = Path(path)
    done = None
    if resume:
        try:
            stored = pickle.loads(path.read_bytes())
            found, done = stored.get("settings", {}), stored["state"]
        except (pickle.UnpicklingError, *DAMAGE) as err:
            raise damaged(path, err) from None
        check_settings(path, found, settings)

    def keep(*state):
        with replaced_atomically(path) as tmp:
            tmp.write_bytes(pickle.dumps({"settings": settings, "state": state}))

    return done, keep


def _cell_key(text) -> tuple:
    i, j = (int(v) for v in text.split(","))
    return i, j


class CellStore:
    """The cells of a sweep over a grid ((i, j) -> a JSON-able record), stored as they finish.

    ``done``: the cells an earlier run with the same ``settings`` stored (with ``resume``; else
    none). :meth:`keep` records a finished cell; the running sweep goes to ``<stem>.partial.json``
    beside ``path``, rewritten atomically at most every ``every`` seconds (a kill loses at most
    that much work; rewriting 10,000 cells at every cell would cost more than the cells), so the
    previous complete ``path`` survives until :meth:`finish` writes the new one and removes the
    partial file. Resuming reads the partial file when there is one, else ``path``; a one-line
    ValueError when that is missing or was written for other settings.
    """

    def __init__(
        self,
        path,
        settings: dict,
        *,
        resume: bool,
        encode=lambda value: value,
        decode=lambda record: record,
        every: float = 5.0,
    ):
        self.path, self.settings, self.encode, self.every = Path(path), settings, encode, every
        self.partial = self.path.with_name(f"{self.path.stem}.partial{self.path.suffix}")
        self.cells = {}
        if resume:
            source = self.partial if self.partial.exists() else self.path
            stored = read_store(source, settings)
            try:
                self.cells = dict(stored["cells"])
                self.done = {_cell_key(key): decode(record) for key, record in self.cells.items()}
            except DAMAGE as err:
                raise damaged(source, err) from None
        else:
            self.done = {}
        self._last = time.monotonic()

    def keep(self, key, value) -> None:
        self.cells[f"{key[0]},{key[1]}"] = self.encode(value)
        if time.monotonic() - self._last >= self.every:
            self._write(self.partial, "running")
            self._last = time.monotonic()

    def finish(self, status: str) -> Path:
        """Write every cell kept (and resumed) to ``path``, with the sweep's ``status``."""
        written = self._write(self.path, status)
        self.partial.unlink(missing_ok=True)
        return written

    def _write(self, path, status):
        return write_text_atomically(
            path, json.dumps({"settings": self.settings, "status": status, "cells": self.cells}) + "\n"
        )
