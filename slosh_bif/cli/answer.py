"""``slosh-bif answer``: a question answered by the lightest model whose measured error is within
the tolerance (:mod:`slosh_bif.studies.ladder`)."""

from __future__ import annotations

import json

import numpy as np

from slosh_bif.cli.common import add_params_options, add_tmax_option, out_path, params_of, progress, state0_of
from slosh_bif.report.files import write_text_atomically

__all__ = ["add_commands"]


def _answer(args) -> int:
    from slosh_bif.studies.ladder import answer

    params = params_of(args)
    result = answer(
        args.question,
        params,
        tol=args.tol,
        state0=state0_of(args, params),
        sigma_min=args.sigma_min,
        sigma_max=args.sigma_max,
        tmax=args.tmax,
        progress=progress,
    )
    print(result.summary())
    print(f"ran in {result.seconds:.2f} s")
    r = result.result
    if args.question == "frequency-response":
        if hasattr(r, "pieces"):  # a branch of orbits of (8), in pieces
            branches = [piece.branch for piece in r.pieces]
        else:
            branches = (
                [ob.branch for ob in r.branches] if hasattr(r.branches[0], "measures") else list(r.branches)
            )
        print(
            f"{len(branches)} branch(es), {sum(len(b) for b in branches)} points; special points: "
            + ", ".join(f"{s.kind} {s.p:.5g}" for b in branches for s in b.special)
        )
    elif args.question == "critical-forcing":
        value, kind = (r.Abar_b, r.kind) if hasattr(r, "Abar_b") else (r.Abar_c, r.bounded_by)
        low, high = r.chart.abar_range if hasattr(r, "chart") else (np.nan, np.nan)
        if np.isfinite(value):
            print(
                f"critical forcing at sigma = {params.sigma:g}: Abar = {value:.6g} ({kind}; {_crossing(r)})"
            )
        elif getattr(r, "below_range", False):
            print(
                f"critical forcing at sigma = {params.sigma:g}: below Abar = {low:g}, the range's "
                "bottom: stable orbits with wall contact reach it"
            )
        else:
            where = f"sigma = {params.sigma:g} for Abar in [{low:g}, {high:g}]"
            print(f"no stable orbit with wall contact at {where}")
    elif args.question == "time-response":
        A = r.A if hasattr(r, "A") else None
        print(
            f"slow envelope A from {A[0]:.4g} to {A[-1]:.4g}"
            if A is not None
            else f"{r.status}: {r.message}; max |X| = {np.max(np.abs(r.y[0])):.4g}"
        )
    else:
        print(f"regime: {r}" if isinstance(r, str) else f"regime: {r.regime} ({r.reason})")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        record = dict(
            question=result.question,
            model=result.model,
            reason=result.reason,
            error_estimate=result.error_estimate,
            seconds=result.seconds,
            params=params.as_dict(),
        )
        path = args.out / "answer.json"
        write_text_atomically(path, json.dumps(record, indent=2) + "\n")
        print(f"wrote {path}")
    return 0


def add_commands(sub) -> None:
    ans = sub.add_parser(
        "answer", help="answer a question with the lightest model whose measured error is within --tol"
    )
    ans.add_argument(
        "question", choices=("frequency-response", "critical-forcing", "time-response", "regime")
    )
    add_params_options(ans)
    ans.add_argument(
        "--tol",
        type=float,
        default=0.05,
        help="relative error allowed (for the regime: the misclassification rate; default 0.05)",
    )
    ans.add_argument(
        "--sigma-min",
        type=float,
        default=None,
        help="frequency response: lower end of sigma (default sigma - 3)",
    )
    ans.add_argument(
        "--sigma-max",
        type=float,
        default=None,
        help="frequency response: upper end of sigma (default sigma + 3)",
    )
    add_tmax_option(ans)
    ans.add_argument(
        "--out",
        type=out_path,
        default=None,
        help="output folder for answer.json (the choice, its reason and error estimate)",
    )
    ans.set_defaults(run=_answer)


def _crossing(r) -> str:
    """What crossing the critical forcing does: the slow flow's is a fold of (46) or the end of
    its stable branch (a jump either way); the full model's as its normal form says."""
    if hasattr(r, "Abar_b"):
        return "crossing it is a jump: the stable steady state of (46) ends there"
    return {
        "jump": "crossing it is a jump: the stable orbit folds",
        "soft": "crossing it is soft: a small new motion grows beside the orbit",
        "hard": "crossing it is a jump: the new motion is born unstable",
        "none": "no bifurcation: below it the stable orbit stops touching the walls",
    }.get(r.loss, f"whether crossing it is a jump is {r.loss or 'not computed'}")
