"""A design study over a third parameter: one (sigma, Abar) chart of (9), or of the impact model
(8) or its corrected variant, per value of a parameter of the set (beta, gamma, eps, lam, chi,
...), and how the full model's critical forcing Abar_c (the lowest forcing with a stable periodic
response lost, read off each chart's curves) and the way it is lost (a jump or soft: the
normal-form coefficients along the curves) move with it, beside the slow flow's Abar_b of (46).
Each value's curves are stored as the chart stores them, so that a study stopped part way resumes
where it stopped."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from slosh_bif.model.parameter_file import TANK_KEYS
from slosh_bif.model.params import REAL_FIELDS, Params
from slosh_bif.orbits.impact.problem import VARIANT_NAMES
from slosh_bif.report.files import Resume
from slosh_bif.report.tables import write_rows
from slosh_bif.studies.chart.critical import critical_rows
from slosh_bif.studies.chart.impact import impact_chart
from slosh_bif.studies.chart.output import chart_settings, curve_store
from slosh_bif.studies.chart.result import ChartSettings, check_box
from slosh_bif.studies.chart.smooth import bifurcation_chart

__all__ = [
    "Study",
    "StudyValue",
    "parse_vary",
    "design_study",
    "STUDY_COLUMNS",
    "STUDY_MODELS",
    "write_study_csv",
    "plot_study",
    "least_critical",
]

STUDY_COLUMNS = (
    "value",
    "sigma",
    "Abar_b_slowflow",
    "Abar_c_full",
    "bounded_by",
    "loss",
    "below_box",
    "status",
)

# the models a study charts: (9), the impact model (8) and the corrected impact model
STUDY_MODELS = ("smooth", "impact", "impact-corrected")
_VARIANTS = {"impact": "paper", "impact-corrected": "corrected"}  # the impact models' variants


def parse_vary(text: str, tank: dict | None = None) -> tuple:
    """(name, values) of ``NAME=LO:HI:COUNT``, or a one-line ValueError naming what is wrong.
    NAME is a parameter of the set but sigma and Abar (the chart's axes), or, with the [tank]
    table ``tank`` of a parameter file, a numeric quantity of that table (the fill ``depth``, ...)."""
    name, _, span = str(text).partition("=")
    parts = span.split(":")
    if not name or len(parts) != 3:
        raise ValueError(f"--vary takes NAME=LO:HI:COUNT (e.g. beta=0.1:0.5:5); got {text!r}")
    allowed = [f for f in REAL_FIELDS if f not in ("sigma", "Abar")]
    if tank is not None:
        allowed += [k for k in TANK_KEYS if k not in allowed and k != "shape"]
    if name not in allowed:
        where = (
            "" if tank is not None else " (a tank's quantities, e.g. depth, with --params of a [tank] file)"
        )
        raise ValueError(
            f"--vary varies one of {', '.join(allowed)}{where}; sigma and Abar are the chart's axes; "
            f"got {name!r}"
        )
    try:
        lo, hi, count = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise ValueError(
            f"--vary {name}=LO:HI:COUNT needs two numbers and an integer; got {span!r}"
        ) from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi and count >= 2):
        raise ValueError(f"--vary {name}: need finite LO < HI and COUNT >= 2; got {lo:g}:{hi:g}:{count}")
    return name, np.linspace(lo, hi, count)


@dataclasses.dataclass(frozen=True)
class StudyValue:
    """One value of the study: its ``chart`` (None where it could not be charted, ``reason`` says
    why) and its ``status`` (the chart's, or ``not charted``)."""

    value: float
    chart: object
    status: str
    reason: str = ""


@dataclasses.dataclass(frozen=True)
class Study:
    """The charts of a study over ``name``: one :class:`StudyValue` per value, in order, of the
    model ``orbits`` names ("(9)", "(8)", ...)."""

    name: str
    values: tuple
    sigma_range: tuple
    abar_range: tuple
    orbits: str = "(9)"

    @property
    def complete(self) -> bool:
        return all(v.status == "complete" for v in self.values)


def design_study(
    params: Params,
    state0,
    vary: tuple,
    *,
    box: dict,
    folder,
    resume: bool = False,
    settings: ChartSettings = ChartSettings(),
    progress=None,
    at_value=None,
    model: str = "smooth",
) -> Study:
    """One chart of ``model`` (one of :data:`STUDY_MODELS`) per value of ``vary``, (name, values)
    as :func:`parse_vary` gives them, over ``box`` ({"sigma": range, "Abar": range}), its curves
    stored under ``folder/value-K/curves`` (``resume``: reused from an earlier run with the same
    settings). A value whose set is not admissible (its parameter file's own check) is recorded
    with the reason and skipped; a chart stopped part way (Ctrl-C) stops the study there.
    ``at_value(value)``: the parameter set at a value (a tank converted at its fill depth, say;
    a ValueError where it has none), instead of ``params`` with ``name`` replaced. ``state0``: the
    initial state of the charts' simulations, or a function of a value's parameter set giving it
    (a preset's ``state_for``, scaled with each value's eps, as ``chart`` would start there)."""
    if model not in STUDY_MODELS:
        raise ValueError(f"model must be one of {', '.join(STUDY_MODELS)}; got {model!r}")
    name, values = vary
    say = progress or (lambda message: None)
    sigma_range, abar_range = tuple(box["sigma"]), tuple(box["Abar"])
    done = []
    for k, value in enumerate(values):
        try:
            at = params.replace(**{name: float(value)}) if at_value is None else at_value(float(value))
            check_box(at, sigma_range, abar_range, "Abar")
        except ValueError as err:
            done.append(StudyValue(float(value), None, "not charted", str(err)))
            continue
        say(f"{name} = {value:.6g}: chart {k + 1} of {len(values)}")
        options = dict(switch=True, seeds=settings.seeds, backend="auto")
        if model != "smooth":  # as ``chart --model`` stores it
            options["model"] = model
        start = state0(at) if callable(state0) else state0
        stored = chart_settings(at, start, sigma_range, abar_range, **options)
        store = curve_store(Path(folder) / f"value-{k:03d}" / "curves", stored, resume=resume)
        here = f"{name} = {value:.6g}: "
        chart = _chart(
            model, at, start, (sigma_range, abar_range), settings, Resume(*store), lambda m: say(here + m)
        )
        done.append(StudyValue(float(value), chart, chart.status))
        if chart.status != "complete":
            break
    orbits = VARIANT_NAMES[_VARIANTS[model]] if model in _VARIANTS else "(9)"
    return Study(name, tuple(done), tuple(sigma_range), tuple(abar_range), orbits)


def _chart(model, params, state0, box, settings, resume, say):
    """One value's chart of ``model`` over ``box`` (sigma range, Abar range)."""
    sigma_range, abar_range = box
    if model == "smooth":
        return bifurcation_chart(
            params,
            state0,
            box={"sigma": sigma_range, "Abar": abar_range},
            settings=settings,
            progress=say,
            resume=resume,
        )
    return impact_chart(
        params,
        state0,
        sigma_range=sigma_range,
        abar_range=abar_range,
        settings=settings,
        progress=say,
        variant=_VARIANTS[model],
        resume=resume,
    )


def study_rows(study: Study, points: int = 57):
    """Per value and sigma: Abar_b of (46), Abar_c of the study's model, the kind of curve that sets it, how
    the response is lost there and whether it may lie below the box (``critical.csv``'s columns,
    :func:`~slosh_bif.studies.chart.critical.critical_rows`); a value that was not charted has one
    row with its reason."""
    for v in study.values:
        if v.chart is None or v.chart.status != "complete":
            yield dict(
                value=v.value,
                sigma=np.nan,
                Abar_b_slowflow=np.nan,
                Abar_c_full=np.nan,
                bounded_by="",
                loss="",
                below_box="",
                status=f"not charted: {v.reason}" if v.chart is None else v.status,
            )
            continue
        for row in critical_rows(v.chart, points):
            yield dict(value=v.value, **{k: row[k] for k in STUDY_COLUMNS[1:-1]}, status=v.status)


def write_study_csv(study: Study, path) -> Path:
    return write_rows(study_rows(study), STUDY_COLUMNS, path)


def least_critical(rows, abar_min: float) -> tuple:
    """(least Abar_c over sigma, its sigma, below) of one chart's :func:`critical_rows`: where
    stable orbits reach the box's bottom at some sigma (``below_box``) the least is below the box,
    so it is returned as the box's bottom ``abar_min`` with ``below`` True and no sigma."""
    if any(r["below_box"] for r in rows):
        return abar_min, np.nan, True
    c = np.array([r["Abar_c_full"] for r in rows], dtype=float)
    if not np.any(np.isfinite(c)):
        return np.nan, np.nan, False
    k = int(np.nanargmin(c))
    return float(c[k]), float(rows[k]["sigma"]), False


def plot_study(study: Study, path) -> Path:
    """Left: Abar_c(sigma) of the study's model for each value (a colour a value; solid where the response is
    lost softly, dashed where by a jump, dotted where undetermined) and the slow flow's Abar_b
    (thin); right: against the value, the least Abar_c over sigma and where it is."""
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [1.6, 1]})
    charted = [v for v in study.values if v.chart is not None and v.status == "complete"]
    colours = plt.cm.viridis(np.linspace(0, 1, max(len(charted), 2)))
    least = []
    for v, colour in zip(charted, colours):
        rows = list(critical_rows(v.chart, 201))
        sigma = np.array([r["sigma"] for r in rows])
        c = np.array([r["Abar_c_full"] for r in rows])
        b = np.array([r["Abar_b_slowflow"] for r in rows])
        loss = np.array([r["loss"] for r in rows])
        for style, kinds in (("-", ("soft",)), ("--", ("jump", "hard")), (":", ("undetermined", ""))):
            shown = np.isin(loss, kinds)
            label = f"{study.name} = {v.value:.4g}" if style == "-" else None
            left.plot(sigma, np.where(shown, c, np.nan), style, color=colour, lw=2, label=label)
        left.plot(sigma, b, "-.", color=colour, lw=0.8)
        least.append((v.value, *least_critical(rows, study.abar_range[0])))
    left.set_xlim(*study.sigma_range)
    left.set_ylim(*study.abar_range)
    left.set_xlabel(r"detuning $\sigma$")
    left.set_ylabel(rf"critical forcing $\bar A_c$ of {study.orbits}")
    left.set_title(
        "solid: lost softly; dashed: a jump; dotted: undetermined; dash-dot: the slow flow's Abar_b (46)",
        fontsize=9,
    )
    left.legend(fontsize=8)
    left.grid(alpha=0.3)
    if least:
        value, c, at, below = map(np.array, zip(*least))
        label = r"least $\bar A_c$ over $\sigma$"
        if below.any():  # the least lies below the box there: drawn at its bottom, open
            right.plot(value, c, "-", color="tab:green")
            if not below.all():
                right.plot(value[~below], c[~below], "o", color="tab:green", label=label)
            under = "below the box: lower --abar-min"
            right.plot(value[below], c[below], "v", color="tab:red", mfc="none", label=under)
        else:
            right.plot(value, c, "o-", color="tab:green", label=label)
        twin = right.twinx()
        twin.plot(value, at, "s:", color="0.4", label=r"its $\sigma$")
        twin.set_ylabel(r"$\sigma$ of the least $\bar A_c$")
        right.legend(loc="upper left", fontsize=8)
        twin.legend(loc="upper right", fontsize=8)
    skipped = [v for v in study.values if v.chart is None]
    right.set_xlabel(study.name)
    right.set_ylabel(r"least $\bar A_c$")
    right.set_title(
        "the stable region's lowest point" + (f" ({len(skipped)} value(s) not charted)" if skipped else ""),
        fontsize=9,
    )
    right.grid(alpha=0.3)
    return save_figure(fig, path)
