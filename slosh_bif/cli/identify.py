"""``slosh-bif fit``: the wall's parameters identified from measurements (:mod:`slosh_bif.identify`),
written as fit.json, fit.png and a parameter file the other commands take with ``--params``."""

from __future__ import annotations

import sys
from pathlib import Path

from slosh_bif.cli.common import MAX_WORKERS, add_params_options, out_path, params_of, progress

__all__ = ["add_commands"]


def _fit(args) -> int:
    from slosh_bif.identify.csv_table import read_header

    if not 1 <= args.workers <= MAX_WORKERS:
        raise ValueError(f"--workers takes an integer in [1, {MAX_WORKERS}]; got {args.workers}")

    columns = read_header(args.data)
    if ("sigma" in columns and "A" in columns) or ("f_hz" in columns and "A_m" in columns):
        return _fit_response(args)
    if "v0" in columns and "v_out" in columns:
        return _fit_records(args)
    if "tau" in columns and args.record == "steady":  # the reader names a missing X
        return _fit_steady(args)
    if "tau" in columns and ("A" in columns or "X" in columns):
        return _fit_time_series(args)
    raise ValueError(
        f"{args.data}: its header names neither a frequency response (sigma, A[, std, sweep] or f_hz, "
        "A_m[, std_m, sweep] with a tank file), a free decay (tau, A[, std] or tau, X) nor impact "
        f"records (v0, v_out[, std]); has {', '.join(columns) or 'no header'}"
    )


def _free(args, allowed, what: str) -> tuple:
    """The names of ``--free``, each one of ``allowed`` (``what``: the data they are fitted to)."""
    free = tuple(name.strip() for name in args.free.split(",") if name.strip())
    if not free or any(name not in allowed for name in free):
        raise ValueError(
            f"--free takes a comma-separated subset of {', '.join(allowed)} for {what}; got {args.free!r}"
        )
    return free


def _fit_response(args) -> int:
    from slosh_bif.identify.response_data import read_response_data
    from slosh_bif.identify.response_fit import MODEL_NAMES, MODELS, RESPONSE_FREE, fit_response
    from slosh_bif.identify.response_output import write_response_fit
    from slosh_bif.model.parameter_file import read_site
    from slosh_bif.simulation.sweep import local_pool

    model = args.model or "slowflow"
    if model not in MODELS + ("auto",):
        raise ValueError(
            f"--model for a frequency response must be one of {', '.join(MODELS)} (the slow flows, the "
            f"smooth model (9), the impact model (8) and the corrected impact model) or auto (the "
            f"lightest that describes the data); got {model!r}"
        )
    free = _free(args, RESPONSE_FREE, "a frequency response")
    base = params_of(args)
    site = read_site(args.params) if args.params is not None else None
    data = read_response_data(args.data, base, site)
    if model == "auto":
        from slosh_bif.identify.response_ladder import fit_by_ladder

        with local_pool(args.workers) as pool:
            fit = fit_by_ladder(data, base, free, seed=args.seed, progress=progress, pool=pool)
        for rung in fit.ladder:
            print(
                f"  {'used' if rung['used'] else 'checked' if rung.get('checked') else 'passed over'}: "
                f"{MODEL_NAMES[rung['model']]}: {rung['why']}"
            )
    else:
        with local_pool(args.workers) as pool:
            fit = fit_response(data, base, free, model=model, seed=args.seed, progress=progress, pool=pool)
    paths = write_response_fit(fit, data, base, args.out)
    by = MODEL_NAMES[fit.model]
    misfit = "chi-square" if fit.scale_known else "residual sum of squares"
    return _report(
        fit,
        paths,
        f"{fit.points} response points, {by}: {misfit} {_sum_of_squares(fit):.4g}, rms residual "
        f"{fit.rms:.3g}" + _goodness_line(fit),
    )


def _fit_time_series(args) -> int:
    from slosh_bif.identify.time_series import DECAY_FREE, FORCED_FREE, fit_time_series, read_time_record
    from slosh_bif.identify.time_series_output import write_time_series_fit
    from slosh_bif.identify.transient_record import TRANSIENT_MODELS

    if args.model in TRANSIENT_MODELS:
        return _fit_transient(args)

    forced = args.record == "forced"
    kind = "a forced record (A0 and psi0 are fitted with them)" if forced else "a free decay (and A0)"
    free = _free(args, FORCED_FREE if forced else DECAY_FREE, kind)
    base = params_of(args)
    data = read_time_record(args.data)
    fit = fit_time_series(
        data, base, free, forced=forced, model=args.model or "slowflow", seed=args.seed, progress=progress
    )
    paths = write_time_series_fit(fit, data, base, args.out)
    return _report(
        fit,
        paths,
        f"{fit.points} envelope points, {kind.split(' (')[0]} by the slow flow ({fit.model}): rms "
        f"residual {fit.rms:.3g}" + _goodness_line(fit),
    )


def _fit_transient(args) -> int:
    from slosh_bif.identify.transient_fit import TRANSIENT_FREE, fit_transient
    from slosh_bif.identify.transient_output import write_transient_fit
    from slosh_bif.identify.transient_record import read_transient_record
    from slosh_bif.simulation.sweep import local_pool

    forced = args.record == "forced"
    free = _free(
        args, TRANSIENT_FREE, f"a {'forced transient' if forced else 'free decay'} by the full model"
    )
    base = params_of(args)
    record = read_transient_record(args.data)
    with local_pool(args.workers) as pool:
        fit = fit_transient(
            record, base, free, model=args.model, forced=forced, progress=progress, pool=pool, seed=args.seed
        )
    paths = write_transient_fit(fit, record, base, args.out)
    misfit = "chi-square" if fit.scale_known else "residual sum of squares"
    return _report(
        fit,
        paths,
        f"{fit.points} of {len(record)} samples (to the horizon tau = {fit.horizon:.4g}), "
        f"{fit.as_dict()['model'].split(' by ')[1]}: {misfit} {_sum_of_squares(fit):.4g}, rms residual "
        f"{fit.rms:.3g}" + _goodness_line(fit),
    )


def _fit_steady(args) -> int:
    from slosh_bif.identify.steady_fit import STEADY_FREE, fit_steady_record
    from slosh_bif.identify.steady_output import write_steady_fit
    from slosh_bif.identify.steady_record import read_steady_record
    from slosh_bif.simulation.sweep import local_pool

    free = _free(args, STEADY_FREE, "a settled forced record")
    base = params_of(args)
    record = read_steady_record(args.data)
    with local_pool(args.workers) as pool:
        fit = fit_steady_record(
            record, base, free, model=args.model or "smooth", seed=args.seed, progress=progress, pool=pool
        )
    paths = write_steady_fit(fit, record, base, args.out)
    misfit = "chi-square" if fit.scale_known else "residual sum of squares"
    sigmas = [curve["sigma"] for curve in fit.orbits]
    what = f"{len(sigmas)} settled records (sigma = {', '.join(f'{x:g}' for x in sigmas)})"
    return _report(
        fit,
        paths,
        f"{fit.points} samples of {what if len(sigmas) > 1 else 'a settled record'}, "
        f"{fit.as_dict()['model'].split(' by ')[1]}: {misfit} "
        f"{_sum_of_squares(fit):.4g}, rms residual {fit.rms:.3g}" + _goodness_line(fit),
    )


def _report(fit, paths, headline: str) -> int:
    """Print the headline, the estimates and the files; 3 where the fit did not converge or the
    fitted model does not describe the data (said in one line, with the p-value)."""
    print(headline)
    _print_estimates(fit)
    print("wrote " + ", ".join(str(p) for p in paths))
    status = 0
    if not getattr(fit, "describes", True):
        print(
            f"slosh-bif fit: {fit.goodness.statement}; the intervals above are conditional on it",
            file=sys.stderr,
        )
        status = 3
    if not fit.converged:
        print(
            f"slosh-bif fit: the fit did not converge ({fit.message}); its best point is written",
            file=sys.stderr,
        )
        status = 3
    return status


def _print_estimates(fit) -> None:
    level = "95 %" if getattr(fit, "describes", True) else "95 % if the model were right"
    for name, e in fit.estimate.items():
        if "wald_95" in e:
            profile = e.get("profile_95")
            print(
                f"  {name} = {e['value']:.6g} +- {e['std']:.2g} ({level}: Wald [{e['wald_95'][0]:.6g}, "
                f"{e['wald_95'][1]:.6g}]"
                + (f", profile [{_bound(profile[0])}, {_bound(profile[1])}])" if profile else ")")
            )
        else:
            print(f"  {name} = {e['value']} (consistent at 95 %: {e.get('consistent_95')})")
    if fit.not_identifiable:
        print(f"  not identifiable: {fit.not_identifiable}")


def _goodness_line(fit) -> str:
    """The fit's p-value beside the misfit (with the std given: chi-square's tail; else the
    residuals' structure, with the estimated noise)."""
    g = fit.goodness
    if g is None:
        return ""
    noise = "" if fit.scale_known else f", estimated noise {g.noise:.3g}"
    return f" (p = {g.p_value:.2g}{noise})"


def _sum_of_squares(fit) -> float:
    return float(fit.residuals @ fit.residuals)


def _bound(value) -> str:
    return "unbounded" if value is None else f"{value:.6g}"


def _fit_records(args) -> int:
    from slosh_bif.identify import FREE_NAMES, fit_wall, read_impact_records
    from slosh_bif.identify.output import write_fit

    if args.model is not None:
        raise ValueError(
            "--model applies to a frequency response; impact records are fitted by eq. (21) itself"
        )
    free = _free(args, FREE_NAMES, "impact records (they speak to the restitution law)")
    base = params_of(args)
    records = read_impact_records(args.data)
    fit = fit_wall(records, base, free)
    paths = write_fit(fit, records, base, args.out)
    v = fit.values
    print(
        f"{fit.records} impact records: eq. (21) with n = {v['n']}, pbar = {v['pbar']} (q = "
        f"{fit.q:.4g}): C = {fit.C:.6g} +- {fit.C_std:.2g} "
        f"(95 %: [{fit.C_interval[0]:.6g}, {fit.C_interval[1]:.6g}]), rms residual in kappa {fit.rms:.2g}"
    )
    for name, e in fit.estimate.items():
        interval = e.get("interval_95")
        print(
            f"  {name} = {e['value']:.6g}"
            + (
                f" +- {e['std']:.2g} (95 %: [{interval[0]:.6g}, {interval[1]:.6g}])"
                if interval
                else f" ({e.get('profile', '')})"
            )
        )
    if fit.not_identifiable:
        print(f"  not identifiable: {fit.not_identifiable}")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


def add_commands(sub) -> None:
    """Register ``fit`` on the ``slosh-bif`` subparsers ``sub``."""
    fit = sub.add_parser(
        "fit",
        help="identify the wall's (and vessel's) parameters from measurements, with intervals: a "
        "frequency response (by the slow flows or the orbits of 9 or 8), a free decay or forced record "
        "(by the slow flow in time, or settled by the orbits of 9 or 8) or impact records (by eq. 21)",
        epilog="data: a CSV with the columns sigma, A (the response's first-harmonic amplitude) and "
        "optionally std and sweep (up or down): a frequency response (or f_hz, A_m[, std_m, sweep] in "
        "Hz and metres with --params TANK_FILE); tau, A[, std] (the envelope) or tau, X (the vessel's "
        "displacement): a free decay or, with --record forced, a forced transient, or with --record "
        "steady (tau, X[, std, sigma]) a settled forced record (with sigma: one at each frequency, fitted "
        "together); or v0 (incoming "
        "speed), v_out (outgoing speed) and optionally std: impact records",
    )
    add_params_options(fit)
    fit.add_argument(
        "--data",
        type=Path,
        required=True,
        help="CSV: sigma, A[, std, sweep]; f_hz, A_m[, std_m, sweep]; tau, A[, std] or tau, X; v0, v_out",
    )
    fit.add_argument(
        "--free",
        required=True,
        help="the parameters to fit, comma-separated: of lam, chi, gamma, Abar, eps (by the orbits), n, "
        "pbar (profiled, by the slow flows) for a response; of lam, chi, gamma (and Abar, forced; and "
        "eps, settled or by the trajectory of 9 or 8) for a record in time; of lam, chi, pbar for impact "
        "records (lam and chi together: only their combination is determined where the model has C of "
        "eq. 21 alone)",
    )
    fit.add_argument(
        "--model",
        default=None,
        help="for a frequency response: slowflow (default; eq. 46 with the law 21), corrected (the "
        "corrected slow flow, the wall's measured law), smooth (the stable orbits of the full model 9), "
        "impact (the stable orbits of the vibro-impact model 8), impact-corrected (of the corrected "
        "impact model) or auto (the lightest of slowflow, corrected, impact, smooth that describes the "
        "data within its checked range, the others reported with why)",
    )
    fit.add_argument(
        "--record",
        choices=("decay", "forced", "steady"),
        default="decay",
        help="for a record in time (tau, A or tau, X): a free decay (default) or a forced transient, by "
        "the slow flow (45) (with --model smooth, impact or impact-corrected and tau, X[, std]: by the "
        "trajectory of 9 or 8 from rest, up to the horizon the record is predictable to), or steady: a "
        "settled forced record (tau, X[, std], tau the forcing's phase) by the orbit of --model smooth "
        "(default; eq. 9), impact (8) or impact-corrected, at the parameter set's sigma (or the file's "
        "sigma column: records at several frequencies) and Abar",
    )
    fit.add_argument("--seed", type=int, default=0, help="seed of the fit's extra starts (default 0)")
    fit.add_argument(
        "--workers",
        type=int,
        default=1,
        help="processes that run an orbit fit's starts and profiles side by side (a frequency response or "
        "a settled record; the same result; default 1: one after another)",
    )
    fit.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    fit.set_defaults(run=_fit)
