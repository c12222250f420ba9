"""``slosh-bif info`` (a preset's parameters and restitution quantities, eqs. 21, 31, 36, 40),
``slosh-bif derive`` (regenerate or check the generated code) and ``slosh-bif compile`` (build the
compiled loops ahead of time: :mod:`slosh_bif.flows.ahead_of_time`)."""

from __future__ import annotations

import importlib.util
import json
import os
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
    from slosh_bif.flows import ahead_of_time

    path = ahead_of_time.module_path()
    if ahead_of_time.disabled():
        print(
            f"{ahead_of_time.DISABLE}={os.environ.get(ahead_of_time.DISABLE)} turns the module built ahead "
            "of time off: unset it to build one",
            file=sys.stderr,
        )
        return 2
    if ahead_of_time.load() is not None and not args.force:
        print(f"the compiled loops are built ahead of time: {path}")
        return 0
    reason = ahead_of_time.failure(path)
    if reason is not None:
        print(f"the last build failed ({reason}); trying again", file=sys.stderr)
    print(
        "building the compiled loops ahead of time (5-30 s; numba's pycc and a C compiler)", file=sys.stderr
    )
    start = time.perf_counter()
    ahead_of_time.build(path)  # RuntimeError, reported by main, says what was missing
    print(f"built {path} in {time.perf_counter() - start:.1f} s")
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
        help="build the compiled loops (the integrator of (9), the periodic QR) ahead of time, so that "
        "commands start without importing numba (done in the background after the first command otherwise)",
    )
    compile_.add_argument("--force", action="store_true", help="build again even when built")
    compile_.set_defaults(run=_compile)
