"""Parameter files: a parameter set (and optionally its initial condition and time window) in TOML
or JSON, the alternative to a preset on every command (``--params FILE``).

A file holds exactly one of two tables:

* ``[params]``: the dimensionless parameters of :class:`~slosh_bif.model.params.Params` (every
  field; see its table for symbols and ranges);
* ``[tank]``: a tank on its site in SI units, converted by :func:`~slosh_bif.model.tank.tank_model`:
  ``shape`` ("cylinder" or "rectangle"), ``depth``, ``radius`` or ``length`` and ``width``,
  ``density``, ``height``, ``structure_mass``, ``structure_frequency``, ``damping_ratio``,
  ``excitation_frequency``, ``ground_acceleration``, ``clearance``, and the wall's ``lam``,
  ``chi``, ``n``, ``pbar`` (the paper's values when absent).

and optionally ``[initial]`` with ``uv0 = [u, u', v, v']`` (the absolute coordinates of eq. 5, as
the presets give them; default the kicked start of Figs. 9 and 10) and ``window = [tau0, tau1]``
(what ``simulate`` draws; default [0, 600]). Unknown keys, missing ones and values out of range
are one-line errors naming the key and the file. :func:`render_parameter_file` makes the TOML that
:func:`read_parameter_file` reads back to the same :class:`Params`.
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np

from slosh_bif.model.params import FIELDS, Params
from slosh_bif.model.presets import KICKED, Preset
from slosh_bif.model.tank import WALL_DEFAULTS, Site, Tank, tank_model

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = [
    "read_parameter_file",
    "read_site",
    "read_tank_table",
    "tank_params",
    "render_parameter_file",
    "TANK_KEYS",
]

_TANK = tuple(f.name for f in dataclasses.fields(Tank))
_SITE = tuple(f.name for f in dataclasses.fields(Site))
TANK_KEYS = _TANK + _SITE + tuple(WALL_DEFAULTS)
_WINDOW = (0.0, 600.0)


def _load(path: Path) -> dict:
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise ValueError(f"cannot read the parameter file {path}: {err.strerror or err}") from None
    except UnicodeDecodeError:
        raise ValueError(f"the parameter file {path} is not a text file (TOML or JSON in UTF-8)") from None
    try:
        data = json.loads(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    except (ValueError, tomllib.TOMLDecodeError) as err:
        kind = "JSON" if path.suffix.lower() == ".json" else "TOML"
        raise ValueError(f"{path} is not valid {kind}: {err}") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path}: the file must hold tables (params or tank, and initial)")
    return data


def _table(data, name, path, allowed, required=()):
    table = data.get(name, {})
    if not isinstance(table, dict):
        raise ValueError(f"{path}: [{name}] must be a table")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise ValueError(f"{path}: unknown key {unknown[0]!r} in [{name}]; known: {', '.join(allowed)}")
    missing = [key for key in required if key not in table]
    if missing:
        raise ValueError(f"{path}: [{name}] needs {', '.join(missing)}")
    return table


def _numbers(value, count, key, path):
    ok = (
        isinstance(value, list)
        and len(value) == count
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
    )
    if not ok:
        raise ValueError(f"{path}: {key} must be {count} finite numbers; got {value!r}")
    return tuple(float(v) for v in value)


def _params_of(data, path) -> tuple[Params, str]:
    if ("params" in data) == ("tank" in data):
        raise ValueError(f"{path}: give exactly one of the tables [params] and [tank]")
    try:
        if "params" in data:
            return Params(**_table(data, "params", path, FIELDS, FIELDS)), "parameters"
        table = _table(
            data,
            "tank",
            path,
            TANK_KEYS,
            (
                "shape",
                "depth",
                "structure_mass",
                "structure_frequency",
                "excitation_frequency",
                "ground_acceleration",
                "clearance",
            ),
        )
        return tank_params(table), f"{table['shape']} tank converted by slosh_bif.model.tank"
    except (TypeError, ValueError) as err:
        raise ValueError(f"{path}: {err}") from None


def tank_params(table: dict) -> Params:
    """The parameters of (9) of a [tank] table (tank, site and wall keys, SI units), converted by
    :func:`~slosh_bif.model.tank.tank_model`; a one-line ValueError for a value out of range."""
    tank = Tank(**{k: v for k, v in table.items() if k in _TANK})
    site = Site(**{k: v for k, v in table.items() if k in _SITE})
    return tank_model(tank, site, wall={k: v for k, v in table.items() if k in WALL_DEFAULTS}).params


def read_tank_table(path) -> dict | None:
    """The [tank] table of a parameter file (checked as :func:`read_parameter_file` checks it), or
    None for a file of dimensionless [params]: what a study over a tank quantity varies."""
    path = Path(path)
    read_parameter_file(path)
    return _load(path).get("tank")


def read_parameter_file(path) -> Preset:
    """The file's parameter set as a :class:`~slosh_bif.model.presets.Preset` named after the file
    (what every command takes from ``--preset`` or ``--params``)."""
    path = Path(path)
    data = _load(path)
    unknown = sorted(set(data) - {"params", "tank", "initial"})
    if unknown:
        raise ValueError(f"{path}: unknown table {unknown[0]!r}; known: params, tank, initial")
    params, source = _params_of(data, path)
    initial = _table(data, "initial", path, ("uv0", "window"))
    uv0 = _numbers(initial["uv0"], 4, "uv0", path) if "uv0" in initial else KICKED
    window = _numbers(initial["window"], 2, "window", path) if "window" in initial else _WINDOW
    if not 0 <= window[0] < window[1]:
        raise ValueError(f"{path}: window must be [tau0, tau1] with 0 <= tau0 < tau1; got {list(window)}")
    return Preset(path.stem, params, uv0, window, note=f"from {path.name} ({source})")


def read_site(path) -> Site | None:
    """The [tank] table's site (its excitation frequency and clearance: the units of measured data
    in Hz and metres), or None for a file of dimensionless [params]."""
    path = Path(path)
    data = _load(path)
    read_parameter_file(path)  # the whole file checked first
    if "tank" not in data:
        return None
    return Site(**{k: v for k, v in data["tank"].items() if k in _SITE})


def _plain(value):
    """A value as TOML takes it (numpy numbers as Python's), or a TypeError naming it."""
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"cannot write {value!r} to a parameter file")
    return int(value) if isinstance(value, (int, np.integer)) else float(value)


def render_parameter_file(
    *, params: Params | None = None, tank: dict | None = None, uv0=None, window=None, comment: str = ""
) -> str:
    """The TOML text of a parameter file with ``params`` (a [params] table) or ``tank`` (a [tank]
    table of :data:`TANK_KEYS`), and [initial] when ``uv0`` or ``window`` is given; ``comment`` lines
    lead the file. :func:`read_parameter_file` reads it back to the same :class:`Params`."""
    if (params is None) == (tank is None):
        raise ValueError("give exactly one of params and tank")
    import tomli_w

    document = {}
    if params is not None:
        document["params"] = {name: _plain(getattr(params, name)) for name in FIELDS}
    else:
        unknown = sorted(set(tank) - set(TANK_KEYS))
        if unknown:
            raise ValueError(f"unknown tank key {unknown[0]!r}; known: {', '.join(TANK_KEYS)}")
        document["tank"] = {key: _plain(value) for key, value in tank.items() if value is not None}
    initial = {
        name: [float(v) for v in value]
        for name, value in (("uv0", uv0), ("window", window))
        if value is not None
    }
    if initial:
        document["initial"] = initial
    head = "".join(f"# {line}\n" if line else "#\n" for line in comment.splitlines())
    return head + tomli_w.dumps(document)
