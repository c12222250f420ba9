"""The ``slosh-bif`` command line.

Subcommands:

* ``info``     - a preset's parameters and the derived restitution quantities (eqs. 21, 31, 36, 40);
* ``frc``      - the frequency-response curve of the slow flow (45)/(46) by continuation in sigma;
* ``critical`` - the critical forcing Abar_b(sigma) by continuation of the fold and end conditions;
* ``shoot``    - periodic orbits of the smooth model (9) by shooting, continued in sigma, with
  folds, branch points, period doublings and Neimark-Sacker points, and the branches born there;
* ``compare``  - the slow-flow curve (46) against the shooting branches over the same sigma range;
* ``trust``    - ``compare`` over a grid of eps, beta and n: where the slow flow can be trusted;
* ``simulate`` - a time response of the smooth model (9) or the vibro-impact model (8), optionally
  with the noise of (47), classified into a response regime;
* ``regimes``  - a map of response regimes over (sigma, Abar), computed in parallel;
* ``figures``  - the paper's Figs. 3 and 6-15, regenerated from scratch as PNG files;
* ``derive``   - regenerate the generated code from the sympy derivations (``--check``: verify it).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

from . import manifold, restitution
from .presets import PRESETS, get_preset

__all__ = ["main"]


def _add_params_options(parser):
    parser.add_argument("--preset", required=True, choices=sorted(PRESETS), help="parameter set of a figure of the paper")
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="override one parameter (repeatable), e.g. --set Abar=2 --set n=10",
    )


def _add_range_options(parser):
    parser.add_argument("--sigma-min", type=float, default=None, help="lower end of the sigma range (default -6)")
    parser.add_argument("--sigma-max", type=float, default=None, help="upper end of the sigma range (default 8)")
    parser.add_argument("--out", type=Path, required=True, help="output folder (created if missing)")


def _params(args):
    return get_preset(args.preset).params.with_overrides(args.overrides)


def _info(args) -> int:
    preset = get_preset(args.preset)
    params = _params(args)
    P = params
    kappa_unit = float(restitution.kappa(1.0, P.lam, P.chi, P.n, P.pbar))
    rho_unit = float(restitution.rho(kappa_unit))
    report = {
        "preset": preset.name,
        "note": preset.note,
        "params": P.as_dict(),
        "p": P.p,
        "initial_state": dict(zip(["X", "Xd", "w", "wd"], preset.state0.tolist())),
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
    print("initial state [X, X', w, w'] = " + ", ".join(f"{v:.6g}" for v in preset.state0))
    print(f"kappa at unit impact speed (eq. 21) = {kappa_unit:.10g}")
    if "kappa_newtonian" in report:
        print(f"kappa Newtonian (eq. 40)            = {report['kappa_newtonian']:.10g}")
    print(f"rho (eq. 31)                        = {rho_unit:.10g}")
    print(f"A_min (eq. 36)                      = {report['A_min_at_unit_speed']:.10g}")
    print(f"alpha_min (eq. 36)                  = {report['alpha_min_at_unit_speed']:.10g}")
    return 0


def _sigma_range(args, default=(-6.0, 8.0)):
    lo = default[0] if args.sigma_min is None else args.sigma_min
    hi = default[1] if args.sigma_max is None else args.sigma_max
    if not lo < hi:
        raise ValueError(f"--sigma-min must be below --sigma-max; got {lo} and {hi}")
    return lo, hi


def _frc(args) -> int:
    from .frc_output import plot_frc, write_frc_csv
    from .steady_states import frequency_response

    params = _params(args)
    lo, hi = _sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    fr = frequency_response(params, sigma_min=lo, sigma_max=hi)
    csv_path, png_path = write_frc_csv(fr, args.out / "frc.csv"), plot_frc(fr, args.out / "frc.png")
    for k, branch in enumerate(fr.branches):
        branch.save(args.out / f"frc_branch{k}.npz")
        specials = ", ".join(f"{s.kind} at sigma = {s.p:.10g} (A = {s.x[0]:.6g})" for s in branch.special)
        print(f"component {k}: {len(branch)} points, {branch.message}; {specials}")
    print(f"wrote {csv_path}, {png_path}")
    return 0


def _critical(args) -> int:
    from .critical import critical_curve
    from .frc_output import plot_critical, write_critical_csv

    params = _params(args)
    lo, hi = _sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    curve = critical_curve(params, lo, hi, progress=_progress)
    csv_path, png_path = write_critical_csv(curve, args.out / "critical.csv"), plot_critical(curve, args.out / "critical.png")
    at = float(np.interp(params.sigma, curve.sigma, curve.Abar_b)) if curve.sigma[0] <= params.sigma <= curve.sigma[-1] else None
    if at is not None:
        verdict = "steady states on S+ exist" if params.Abar >= at else "no steady state on S+ (expect a strongly modulated or non-resonant response)"
        print(f"at the preset's sigma = {params.sigma:g}: Abar_b = {at:.6g}; Abar = {params.Abar:g}: {verdict}")
    print(f"{len(curve.sigma)} points ({len(curve.fold_branches)} fold curve(s)); wrote {csv_path}, {png_path}")
    return 0


def _progress(message):
    print(f"  {message}", file=sys.stderr, flush=True)


def _throttled(report, every=1.0, *, passes=lambda message: "point" not in message):
    """A progress callback that passes on at most one message a second (and every message for
    which ``passes`` is true: by default each that is not about a single point, e.g. a new branch)."""
    import time

    last = [-1e9]

    def callback(message):
        now = time.monotonic()
        if now - last[0] >= every or passes(message):
            last[0] = now
            report(message)

    return callback


def _start_orbit(params, args):
    """A converged 2pi-orbit near --guess, or near the strobe states of a simulation from the
    preset's initial state (the last of --settle periods, then up to 49 before it)."""
    from .integrator import integrate_grid
    from .shooting import ShootingProblem, orbit_at

    problem = ShootingProblem(params, segments=args.segments)
    if args.guess is not None:
        guesses = [np.array(args.guess, dtype=float)]
    else:
        strobes = integrate_grid(params, get_preset(args.preset).state0, 2 * np.pi * np.arange(args.settle + 1))
        guesses = list(strobes[::-1][:50])
    for k, y0 in enumerate(guesses):
        orbit = orbit_at(problem, problem.initial_states(y0), params.sigma, tol=1e-9)
        if orbit.converged:
            _progress(f"start orbit at sigma = {params.sigma:g}: |X(0)| = {abs(orbit.y0[0]):.4g}, multipliers |mu| = " + ", ".join(f"{abs(m):.4g}" for m in orbit.multipliers) + f" ({orbit.message})")
            return orbit.y0
    where = "--guess" if args.guess is not None else f"the last strobe states of a {args.settle}-period simulation"
    raise ValueError(f"no periodic orbit found near {where} at sigma = {params.sigma:g}; pass --guess X,Xd,w,wd or change --settle")


def _family(args, params, lo, hi):
    from .orbits import slow_flow_start, trace_orbits

    if args.start == "slow-flow":
        sigma0, orbit = slow_flow_start(params, lo, hi, segments=args.segments)
        _progress(f"start orbit from the slow flow at sigma = {sigma0:.5g}: |X(0)| = {abs(orbit.y0[0]):.4g} ({orbit.message})")
        params, y0 = params.replace(sigma=sigma0), orbit.y0
    else:
        y0 = _start_orbit(params, args)
    return trace_orbits(params, y0, p_min=lo, p_max=hi, segments=args.segments, switch=not args.no_switch, max_branches=args.max_branches, progress=_throttled(_progress))


def _shoot(args) -> int:
    from .orbit_output import plot_family, write_branch_csv

    params = _params(args)
    lo, hi = _sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    family = _family(args, params, lo, hi)
    csv_path, png_path = write_branch_csv(family, args.out / "branch.csv"), plot_family(family, args.out / "branch.png")
    for k, ob in enumerate(family.branches):
        ob.branch.save(args.out / f"branch{k}_{ob.name}.npz")
    print(family.summary())
    print(f"wrote {csv_path}, {png_path}")
    return 0


def _compare(args) -> int:
    from .orbit_output import compare_rows, compare_table, plot_compare, write_compare_csv
    from .steady_states import frequency_response

    params = _params(args)
    lo, hi = _sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    fr = frequency_response(params, sigma_min=lo, sigma_max=hi)
    family = _family(args, params, lo, hi)
    rows = list(compare_rows(family, fr, np.linspace(lo, hi, args.grid)))
    csv_path, png_path = write_compare_csv(rows, args.out / "compare.csv"), plot_compare(family, fr, rows, args.out / "compare.png")
    table = compare_table(rows)
    (args.out / "compare.txt").write_text(table + "\n")
    print(table)
    print(f"wrote {csv_path}, {png_path}, {args.out / 'compare.txt'}")
    return 0


def _floats(text):
    return [float(v) for v in text.split(",")]


def _trust(args) -> int:
    from .trust import trust_map
    from .trust_output import plot_trust_map, trust_table, write_trust_csv

    base = _params(args)
    lo, hi = _sigma_range(args)
    args.out.mkdir(parents=True, exist_ok=True)
    total = len(args.eps) * len(args.beta) * len(args.n)
    _progress(f"{total} parameter sets, each a frequency-response curve of (46) and a family of orbits of (9) (seconds to a minute each)")

    def report(point, done, total):
        _progress(f"{done}/{total}: eps = {point.eps:g}, beta = {point.beta:g}, n = {point.n}: {point.status}, {point.seconds:.1f} s")

    points = trust_map(base, eps=args.eps, beta=args.beta, n=args.n, sigma_min=lo, sigma_max=hi, grid=args.grid, switch=not args.no_switch, max_branches=args.max_branches, max_workers=args.workers, progress=report)
    table = trust_table(points)
    (args.out / "trust_map.txt").write_text(table + "\n")
    csv_path, png_path = write_trust_csv(points, args.out / "trust_map.csv"), plot_trust_map(points, args.out / "trust_map.png")
    print(table)
    print(f"wrote {csv_path}, {png_path}, {args.out / 'trust_map.txt'}")
    return 0


def _add_shooting_options(parser):
    parser.add_argument("--segments", type=int, default=4, help="arcs of multiple shooting per period (default 4)")
    parser.add_argument("--guess", type=_floats, default=None, metavar="X,Xd,w,wd", help="state at tau = 0 near the start orbit (default: from a simulation)")
    parser.add_argument("--start", choices=("simulation", "slow-flow"), default="simulation", help="start orbit: Newton from a simulation at the preset's sigma (default), or from the leading-order motion of a stable steady state of (46) in the range (no simulation)")
    parser.add_argument("--settle", type=int, default=150, help="periods simulated from the preset's initial state for the start guess (default 150)")
    parser.add_argument("--max-branches", type=int, default=6, help="branches traced at most, the primary one included (default 6)")
    parser.add_argument("--no-switch", action="store_true", help="trace the primary branch only")


def _simulate(args) -> int:
    from .regimes import classify
    from .sim_output import plot_simulation, write_summary, write_trajectory
    from .simulate import simulate

    preset = get_preset(args.preset)
    params = _params(args)
    tmax = args.tmax if args.tmax is not None else float(preset.t_window[1])
    noise = preset.noise_std if args.noise is None else args.noise
    if args.transient is not None and not (0 <= args.transient < tmax):
        raise ValueError(f"--transient must be in [0, tmax = {tmax:g}); got {args.transient}")
    args.out.mkdir(parents=True, exist_ok=True)
    report = _throttled(_progress, passes=lambda message: message.startswith("simulated 100"))
    sim = simulate(
        params, preset.state0, tmax, model=args.model, noise_std=noise, seed=args.seed, noise_cutoff=args.noise_cutoff,
        progress=lambda f: report(f"simulated {100 * f:.0f} % of tau in [0, {tmax:g}]"),
    )
    if not sim.success and sim.status != "sticking":
        print(f"slosh-bif simulate: the run stopped early: {sim.message}", file=sys.stderr)
    transient = args.transient if args.transient is not None and args.transient < sim.t[-1] else None
    summary = classify(sim, transient=transient)
    paths = [
        write_trajectory(sim, args.out / "trajectory.npz"),
        write_summary(sim, summary, args.out / "summary.json"),
        plot_simulation(sim, summary, args.out / "simulate.png", title=f"{preset.name} ({args.model} model): {summary.regime}"),
    ]
    print(f"regime: {summary.regime} ({summary.reason}); {sim.message}; {sim.seconds:.2f} s")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


def _regimes(args) -> int:
    from .critical import critical_curve
    from .regimes import regime_map
    from .sim_output import plot_regime_map, write_regime_csv

    params = _params(args)
    lo, hi = _sigma_range(args, default=(-2.0, 4.0))
    if not (0 <= args.abar_min < args.abar_max):
        raise ValueError(f"need 0 <= --abar-min < --abar-max; got {args.abar_min}, {args.abar_max}")
    n_sigma, n_abar = args.grid
    if n_sigma < 1 or n_abar < 1:
        raise ValueError(f"--grid takes two positive integers N M (sigma points, Abar points); got {args.grid}")
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be a positive integer; got {args.workers}")
    args.out.mkdir(parents=True, exist_ok=True)
    report = _throttled(_progress, passes=lambda message: False)
    rmap = regime_map(
        params, get_preset(args.preset).state0, np.linspace(lo, hi, n_sigma), np.linspace(args.abar_min, args.abar_max, n_abar),
        tmax=args.tmax, model=args.model, max_workers=args.workers,
        progress=lambda done, total: report(f"classified {done} of {total} grid points"),
    )
    curve = critical_curve(params, lo, hi)
    paths = [write_regime_csv(rmap, args.out / "regimes.csv"), plot_regime_map(rmap, args.out / "regimes.png", critical=curve)]
    counts = {r: int(np.sum(rmap.regime == r)) for r in sorted(set(rmap.regime.ravel()))}
    print("regimes: " + ", ".join(f"{r} {c}" for r, c in counts.items()))
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


def _figures(args) -> int:
    from .figures import NOTES, make_figures

    paths = make_figures(args.out, quick=args.quick, only=args.only, progress=_progress)
    for path in paths:
        print(f"{path}: {NOTES[path.stem]}")
    return 0


def _bench(args) -> int:
    from .bench import run

    paths = run(args.out, only=args.only, quick=args.quick, repeats=args.repeats, progress=_progress)
    for path in paths:
        print(path)
        if path.name == "integrators_ratios.csv":  # the headline numbers
            print(path.read_text().strip())
    return 0


def _answer(args) -> int:
    from .answer import answer

    params = _params(args)
    result = answer(args.question, params, tol=args.tol, state0=get_preset(args.preset).state0, sigma_min=args.sigma_min,
                    sigma_max=args.sigma_max, tmax=args.tmax, progress=_progress)
    print(result.summary())
    print(f"ran in {result.seconds:.2f} s")
    r = result.result
    if args.question == "frequency-response":
        branches = [ob.branch for ob in r.branches] if hasattr(r.branches[0], "measures") else list(r.branches)
        print(f"{len(branches)} branch(es), {sum(len(b) for b in branches)} points; special points: "
              + ", ".join(f"{s.kind} {s.p:.5g}" for b in branches for s in b.special))
    elif args.question == "critical-forcing":
        value, kind = (r.Abar_b, r.kind) if hasattr(r, "Abar_b") else (r.p, r.kind or "stability change")
        print(f"critical forcing at sigma = {params.sigma:g}: Abar = {value:.6g} ({kind})" if value is not None else "the orbit stays stable down to Abar = 0")
    elif args.question == "time-response":
        A = r.A if hasattr(r, "A") else None
        print(f"slow envelope A from {A[0]:.4g} to {A[-1]:.4g}" if A is not None else f"{r.status}: {r.message}; max |X| = {np.max(np.abs(r.y[0])):.4g}")
    else:
        print(f"regime: {r}" if isinstance(r, str) else f"regime: {r.regime} ({r.reason})")
    return 0


def _derivations_dir() -> Path:
    return Path(__file__).resolve().parent.parent / "derivations"


def _derive(args) -> int:
    script = _derivations_dir() / "generate.py"
    if not script.is_file():
        print(
            f"slosh-bif derive needs the source checkout (derivations/ beside the package); {script} not found. "
            "Install with `pip install -e .` from a clone.",
            file=sys.stderr,
        )
        return 2
    spec = importlib.util.spec_from_file_location("slosh_bif_derivations_generate", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main(["--check"] if args.check else [])


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="slosh-bif",
        description="Continuation and bifurcation analysis of the equivalent mechanical model of strongly "
        "nonlinear liquid sloshing (Farid & Gendelman).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    info = sub.add_parser("info", help="print a preset's parameters and its restitution coefficient, rho and A_min")
    _add_params_options(info)
    info.add_argument("--json", action="store_true", help="print JSON instead of text")
    info.set_defaults(run=_info)

    frc = sub.add_parser("frc", help="frequency-response curve A(sigma) of the slow flow by pseudo-arclength continuation")
    _add_params_options(frc)
    _add_range_options(frc)
    frc.set_defaults(run=_frc)

    critical = sub.add_parser("critical", help="critical forcing Abar_b(sigma) below which no steady state exists on S+")
    _add_params_options(critical)
    _add_range_options(critical)
    critical.set_defaults(run=_critical)

    shoot = sub.add_parser("shoot", help="periodic orbits of the smooth model (9) by shooting, continued in sigma, with their bifurcations")
    _add_params_options(shoot)
    _add_range_options(shoot)
    _add_shooting_options(shoot)
    shoot.set_defaults(run=_shoot)

    compare = sub.add_parser("compare", help="slow-flow curve (46) against the shooting branches of (9) over the same sigma range")
    _add_params_options(compare)
    _add_range_options(compare)
    _add_shooting_options(compare)
    compare.add_argument("--grid", type=int, default=141, help="sigma values compared (default 141)")
    compare.set_defaults(run=_compare)

    trust = sub.add_parser("trust", help="compare over a grid of eps, beta and n: where the slow flow (46) can be trusted")
    _add_params_options(trust)
    _add_range_options(trust)
    trust.add_argument("--eps", type=_floats, default=[0.02, 0.05, 0.1, 0.2], metavar="E1,E2,...", help="mass ratios (default 0.02,0.05,0.1,0.2)")
    trust.add_argument("--beta", type=_floats, default=[0.0, 0.3, 0.5], metavar="B1,B2,...", help="values of beta (default 0,0.3,0.5)")
    trust.add_argument("--n", type=lambda s: [int(v) for v in s.split(",")], default=[6, 10, 20, 50], metavar="N1,N2,...", help="wall exponents n (default 6,10,20,50)")
    trust.add_argument("--grid", type=int, default=141, help="sigma values compared per set (default 141)")
    trust.add_argument("--max-branches", type=int, default=6, help="orbit branches traced per set at most (default 6)")
    trust.add_argument("--no-switch", action="store_true", help="trace the primary orbit branch only (faster; misses stable asymmetric and period-2 orbits)")
    trust.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    trust.set_defaults(run=_trust)

    sim = sub.add_parser("simulate", help="time response of the smooth model (9) or the vibro-impact model (8), with its response regime")
    _add_params_options(sim)
    sim.add_argument("--model", choices=("smooth", "impact"), default="smooth", help="(9) with the wall potential, or (8) with impacts (default smooth)")
    sim.add_argument("--tmax", type=float, default=None, help="end time tau (default: the end of the preset's figure window)")
    sim.add_argument("--noise", type=float, default=None, metavar="STD", help="standard deviation sigma_bar of the noise of eq. 47 (default: the preset's, 0 for most)")
    sim.add_argument("--seed", type=int, default=0, help="seed of the noise (default 0); the same seed gives the same run bit for bit")
    sim.add_argument("--noise-cutoff", type=float, default=10.0, help="highest angular frequency of the band-limited noise (default 10)")
    sim.add_argument("--transient", type=float, default=None, help="tau after which the regime is judged (default: half the run)")
    sim.add_argument("--out", type=Path, required=True, help="output folder (created if missing)")
    sim.set_defaults(run=_simulate)

    regimes = sub.add_parser("regimes", help="map of response regimes over (sigma, Abar), simulated in parallel")
    _add_params_options(regimes)
    _add_range_options(regimes)
    regimes.add_argument("--abar-min", type=float, default=0.1, help="lowest forcing amplitude (default 0.1)")
    regimes.add_argument("--abar-max", type=float, default=3.0, help="highest forcing amplitude (default 3)")
    regimes.add_argument("--grid", type=int, nargs=2, default=(13, 10), metavar=("N", "M"), help="N sigma values by M Abar values (default 13 10)")
    regimes.add_argument("--tmax", type=float, default=600.0, help="simulated time per point; the second half is classified (default 600)")
    regimes.add_argument("--model", choices=("smooth", "impact"), default="smooth", help="model simulated (default smooth)")
    regimes.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    regimes.set_defaults(run=_regimes)

    figures = sub.add_parser("figures", help="regenerate the paper's Figs. 3, 6-15 as PNG files (about 15 s)")
    figures.add_argument("--out", type=Path, required=True, help="output folder (created if missing)")
    figures.add_argument("--only", nargs="+", default=None, metavar="FIG", help="only these figures, e.g. fig10 fig11")
    figures.add_argument("--quick", action="store_true", help="short simulations and coarse grids (a smoke test)")
    figures.set_defaults(run=_figures)

    ans = sub.add_parser("answer", help="answer a question with the lightest model whose measured error is within --tol")
    ans.add_argument("question", choices=("frequency-response", "critical-forcing", "time-response", "regime"))
    _add_params_options(ans)
    ans.add_argument("--tol", type=float, default=0.05, help="relative error allowed (for the regime: the misclassification rate; default 0.05)")
    ans.add_argument("--sigma-min", type=float, default=None, help="frequency response: lower end of sigma (default sigma - 3)")
    ans.add_argument("--sigma-max", type=float, default=None, help="frequency response: upper end of sigma (default sigma + 3)")
    ans.add_argument("--tmax", type=float, default=600.0, help="time response and regime: end time tau (default 600)")
    ans.set_defaults(run=_answer)

    bench = sub.add_parser("bench", help="work-precision charts: frequency-response question, integrators, cost of growth (a few minutes)")
    bench.add_argument("--out", type=Path, required=True, help="output folder (created if missing)")
    bench.add_argument("--only", nargs="+", default=None, choices=("frequency-response", "integration", "growth"), help="only these benchmarks")
    bench.add_argument("--repeats", type=int, default=3, help="timing rounds per point; the median is reported (default 3)")
    bench.add_argument("--quick", action="store_true", help="fewer points and one round (a smoke test, not a measurement)")
    bench.set_defaults(run=_bench)

    derive = sub.add_parser("derive", help="regenerate slosh_bif/_generated from the sympy derivations")
    derive.add_argument("--check", action="store_true", help="exit 1 if the committed generated code is stale")
    derive.set_defaults(run=_derive)
    return parser


def main(argv=None) -> int:
    import warnings

    parser = build_parser()
    args = parser.parse_args(argv)

    def show(message, category, *_args, **_kwargs):  # one line, no source excerpt
        print(f"slosh-bif {args.command}: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        try:
            return args.run(args)
        except ValueError as err:
            print(f"slosh-bif {args.command}: error: {err}", file=sys.stderr)
            return 2
        except RuntimeError as err:  # a method that could not answer says why (no traceback)
            print(f"slosh-bif {args.command}: failed: {err}", file=sys.stderr)
            return 1


if __name__ == "__main__":
    sys.exit(main())
