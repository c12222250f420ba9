"""``slosh-bif tank``: a real tank on its structure under harmonic ground motion, as the model's
dimensionless parameters (:mod:`slosh_bif.model.tank`), printed as a table with each formula's
source and written as a parameter file that every command takes with ``--params``."""

from __future__ import annotations

import dataclasses
import json
import sys
import warnings

from slosh_bif.cli.common import out_path

__all__ = ["add_commands"]


def _tank(args) -> int:
    from slosh_bif.model.parameter_file import (
        read_parameter_file,
        render_parameter_file,
    )
    from slosh_bif.model.tank import WALL_DEFAULTS, Site, Tank, check_wall, tank_model

    geometry = (
        {"radius": args.radius} if args.shape == "cylinder" else {"length": args.length, "width": args.width}
    )
    given = [
        f"--{name}"
        for name in ("radius", "length", "width")
        if getattr(args, name) is not None and name not in geometry
    ]
    if given:
        raise ValueError(
            f"{', '.join(given)} do not describe a {args.shape} (a cylinder takes --radius; a "
            "rectangle --length and --width)"
        )
    missing = [f"--{name}" for name, value in geometry.items() if value is None]
    if missing:
        raise ValueError(f"a {args.shape} needs {' and '.join(missing)}")
    tank = Tank(args.shape, args.depth, density=args.density, height=args.height, **geometry)
    site = Site(
        args.structure_mass,
        args.structure_frequency,
        args.excitation_frequency,
        args.ground_acceleration,
        args.clearance,
        args.damping_ratio,
    )
    wall = {name: getattr(args, name) for name in WALL_DEFAULTS if getattr(args, name) is not None}
    check_wall(wall)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = tank_model(tank, site, wall=wall)
    for w in caught:
        print(f"slosh-bif tank: warning: {w.message}", file=sys.stderr)
    if args.json:
        print(
            json.dumps(
                {
                    "params": model.params.as_dict(),
                    "table": [
                        dict(zip(("quantity", "value", "unit", "source"), (q, float(v), u, s)))
                        for q, v, u, s in model.rows
                    ],
                },
                indent=2,
            )
        )
    else:
        print(f"{'quantity':40s} {'value':>14s}  {'unit':4s}  source")
        for quantity, value, unit, source in model.rows:
            print(f"{quantity:40s} {float(value):14.6g}  {unit:4s}  {source}")
        print("wall (inputs): " + ", ".join(f"{k} = {getattr(model.params, k)}" for k in WALL_DEFAULTS))
    if args.out is not None:
        from slosh_bif.report.files import write_text_atomically

        table = {**dataclasses.asdict(tank), **dataclasses.asdict(site), **wall}
        derived = ", ".join(f"{k} = {v:.6g}" for k, v in model.params.as_dict().items())
        text = render_parameter_file(
            tank=table,
            comment=f"slosh_bif parameter file written by `slosh-bif tank` (SI units)\nconverted: {derived}",
        )
        args.out.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomically(args.out, text)
        if read_parameter_file(args.out).params != model.params:  # what --params will read
            raise RuntimeError(f"{args.out} does not read back to the parameters printed")
        print(f"wrote {args.out} (use it with --params on any command)", file=sys.stderr)
    return 0


def add_commands(sub) -> None:
    """Register ``tank`` on the ``slosh-bif`` subparsers ``sub``."""
    tank = sub.add_parser(
        "tank",
        help="a real tank (geometry, liquid, structure, ground motion) as the model's parameters, "
        "written as a parameter file",
        epilog="exit status: 0, or 2 for bad input (a warning, not an error, where eps or sigma leave the "
        "model's range)",
    )
    tank.add_argument(
        "--shape",
        choices=("cylinder", "rectangle"),
        required=True,
        help="upright circular cylinder or rectangular tank",
    )
    tank.add_argument("--radius", type=float, default=None, help="cylinder radius (m)")
    tank.add_argument(
        "--length", type=float, default=None, help="rectangle: length along the ground motion (m)"
    )
    tank.add_argument(
        "--width", type=float, default=None, help="rectangle: width across the ground motion (m)"
    )
    tank.add_argument("--depth", type=float, required=True, help="liquid depth (m)")
    tank.add_argument(
        "--height",
        type=float,
        default=None,
        help="the closed tank's height (m; the depth must not exceed it)",
    )
    tank.add_argument(
        "--density", type=float, default=1000.0, help="liquid density (kg/m^3, default 1000: water)"
    )
    tank.add_argument(
        "--structure-mass", type=float, required=True, help="mass of the empty tank and its support (kg)"
    )
    tank.add_argument(
        "--structure-frequency",
        type=float,
        required=True,
        help="natural frequency of the empty tank on its support (Hz)",
    )
    tank.add_argument(
        "--damping-ratio", type=float, default=0.02, help="damping ratio of the vessel (default 0.02)"
    )
    tank.add_argument(
        "--excitation-frequency",
        type=float,
        required=True,
        help="frequency of the harmonic ground motion (Hz)",
    )
    tank.add_argument(
        "--ground-acceleration",
        type=float,
        required=True,
        help="amplitude of the ground acceleration (m/s^2)",
    )
    tank.add_argument(
        "--clearance",
        type=float,
        required=True,
        help="travel of the first mode's mass before the liquid hits the wall or roof (m): the model's "
        "unit of length",
    )
    for name, value in (("lam", 0.35), ("chi", 0.2)):
        tank.add_argument(
            f"--{name}",
            type=float,
            default=None,
            help=f"wall law (eq. 9), not given by linear theory (default {value}, the paper's)",
        )
    for name, value in (("n", 50), ("pbar", 0)):
        tank.add_argument(
            f"--{name}",
            type=int,
            default=None,
            help=f"wall law exponent (eq. 9; default {value}, the paper's)",
        )
    tank.add_argument("--json", action="store_true", help="print JSON instead of a table")
    tank.add_argument(
        "--out",
        type=out_path,
        default=None,
        metavar="FILE",
        help="write a parameter file (TOML) for --params",
    )
    tank.set_defaults(run=_tank, out_is_file=True)
