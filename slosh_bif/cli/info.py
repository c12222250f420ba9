"""``slosh-bif info`` (a preset's parameters and restitution quantities, eqs. 21, 31, 36, 40),
``slosh-bif derive`` (regenerate or check the generated code) and ``slosh-bif compile`` (fill numba's
cache with the compiled loops: :mod:`slosh_bif.flows.loops`)."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import sys
import time
from pathlib import Path

from slosh_bif.cli.common import add_params_options, out_path, params_of, preset_of
from slosh_bif.model import manifold, restitution

__all__ = ["add_commands"]


def _info(args) -> int:
    preset = preset_of(args)
    params = params_of(args)
    P = params
    if args.out is not None:  # the set as a parameter file that --params reads
        from slosh_bif.model.parameter_file import render_parameter_file
        from slosh_bif.report.files import write_text_atomically

        text = render_parameter_file(
            params=P,
            uv0=preset.uv0,
            window=preset.t_window,
            comment=f"slosh_bif parameter set '{preset.name}': {preset.note}",
        )
        args.out.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomically(args.out, text)
        print(f"wrote {args.out}", file=sys.stderr)
    kappa_unit = float(restitution.kappa(1.0, P.lam, P.chi, P.n, P.pbar))
    rho_unit = float(restitution.rho(kappa_unit))
    report = {
        "preset": preset.name,
        "note": preset.note,
        "params": P.as_dict(),
        "p": P.p,
        "initial_state": dict(zip(["X", "Xd", "w", "wd"], preset.state_for(P).tolist())),
        "kappa_at_unit_speed": kappa_unit,
        "rho_at_unit_speed": rho_unit,
        "A_min_at_unit_speed": float(manifold.a_min(rho_unit)),
        "alpha_min_at_unit_speed": float(manifold.alpha_min(rho_unit)),
    }
    if P.pbar == 0:
        report["kappa_newtonian"] = float(restitution.kappa_newtonian(P.lam, P.chi, P.n))
    if args.json:
        print(json.dumps(report, indent=2))
        return 0
    print(f"preset {preset.name}: {preset.note}")
    for name, value in report["params"].items():
        print(f"  {name:6s} = {value}")
    print(f"  p      = {P.p}   (dissipation exponent, pbar = 2p - n)")
    print("initial state [X, X', w, w'] = " + ", ".join(f"{v:.6g}" for v in preset.state_for(P)))
    print(f"kappa at unit impact speed (eq. 21) = {kappa_unit:.10g}")
    if "kappa_newtonian" in report:
        print(f"kappa Newtonian (eq. 40)            = {report['kappa_newtonian']:.10g}")
    print(f"rho (eq. 31)                        = {rho_unit:.10g}")
    print(f"A_min (eq. 36)                      = {report['A_min_at_unit_speed']:.10g}")
    print(f"alpha_min (eq. 36)                  = {report['alpha_min_at_unit_speed']:.10g}")
    return 0


def _derivations_dir() -> Path:
    return Path(__file__).resolve().parents[2] / "derivations"


def _derive(args) -> int:
    script = _derivations_dir() / "generate.py"
    if not script.is_file():
        print(
            "slosh-bif derive needs the source checkout (derivations/ beside the package); "
            f"{script} not found. "
            "Install with `pip install -e .` from a clone.",
            file=sys.stderr,
        )
        return 2
    spec = importlib.util.spec_from_file_location("slosh_bif_derivations_generate", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main(["--check"] if args.check else [])


def _compile(args) -> int:
    """Fill numba's on-disk cache: one short call of every compiled loop of (9), of the periodic QR
    and of the exact flow of (8), so that the first real command loads machine code instead of
    compiling it (40-80 s once a machine and a source on 2 cores); and the package's bytecode, which an
    installed wheel has but a checkout run with ``PYTHONDONTWRITEBYTECODE`` never writes (its
    modules are then compiled from source by every command: 0.07 s of a start-up)."""
    import compileall

    import numpy as np

    from slosh_bif.flows.loops import compiled
    from slosh_bif.flows.smooth.arcs import Tape, integrate_arcs, replay_along
    from slosh_bif.flows.smooth.integrator import integrate, integrate_grid
    from slosh_bif.model.presets import get_preset
    from slosh_bif.orbits.floquet import periodic_schur
    from slosh_bif.simulation.direct import SimulationSettings, simulate

    if compiled() is None:
        raise RuntimeError("numba does not import here: the scipy paths run, with nothing to compile")
    print("compiling the loops of (9) and (8) into numba's cache (40-80 s the first time)", file=sys.stderr)
    start = time.perf_counter()
    preset = get_preset("fig10")
    y0 = preset.state_for(preset.params)
    taus = np.linspace(0.0, 0.2, 3)
    integrate(preset.params, y0, (0.0, 0.1))
    integrate_grid(preset.params, y0, taus)
    integrate_arcs(preset.params, np.array([y0, y0]), taus)
    tape = Tape()
    integrate_arcs(preset.params, np.array([y0, y0]), taus, tape=tape)
    replay_along(tape, np.ones((2, 4)))
    periodic_schur([np.eye(4) * 2.0, np.eye(4)])
    impact = get_preset("fig13")
    simulate(impact.params, impact.state_for(impact.params), 1.0, settings=SimulationSettings(model="impact"))
    package = Path(__file__).resolve().parents[1]
    with contextlib.redirect_stdout(io.StringIO()):  # compileall lists what it cannot write
        written = compileall.compile_dir(package, quiet=1, workers=1)
    caches = "numba's cache and the package's bytecode" if written else f"numba's cache; {package} read-only"
    print(f"compiled in {time.perf_counter() - start:.1f} s ({caches}; later commands load them)")
    return 0


def add_commands(sub) -> None:
    """Register this family's commands on the ``slosh-bif`` subparsers ``sub``."""
    info = sub.add_parser(
        "info", help="print a preset's parameters and its restitution coefficient, rho and A_min"
    )
    add_params_options(info)
    info.add_argument("--json", action="store_true", help="print JSON instead of text")
    info.add_argument(
        "--out",
        type=out_path,
        default=None,
        metavar="FILE",
        help="also write the parameter set (overrides applied) as a TOML parameter file for --params",
    )
    info.set_defaults(run=_info, out_is_file=True)

    derive = sub.add_parser("derive", help="regenerate slosh_bif/model/_generated from the sympy derivations")
    derive.add_argument(
        "--check", action="store_true", help="exit 1 if the committed generated code is stale"
    )
    derive.set_defaults(run=_derive)

    compile_ = sub.add_parser(
        "compile",
        help="compile the loops of (9) and (8) into numba's on-disk cache now (a first command does it "
        "otherwise, 40-80 s once a machine)",
    )
    compile_.set_defaults(run=_compile)
