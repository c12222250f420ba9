"""shoot's figure (:func:`slosh_bif.orbits.output.plot_family`) is laid out on fixed margins
instead of by tight_layout: every text must still lie inside the figure, apart from the others."""

import dataclasses

import numpy as np
import pytest

from slosh_bif.model import get_preset
from slosh_bif.orbits import NO_SWITCHING, ShootingSettings, orbit_from_simulation, output, trace_orbits
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.report import plotting


@pytest.fixture(scope="module")
def family():
    """A short stretch of the Fig. 10 symmetric branch (sigma in [2, 3])."""
    P = get_preset("fig10").params.replace(sigma=2.0)
    start = orbit_from_simulation(P, get_preset("fig10").state_for(P), settle=150)
    return trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=2.0, hi=3.0),
    )


def _texts_of(family, monkeypatch, tmp_path):
    """The drawn figure's y labels and tick labels, in display coordinates, and its size."""
    kept = {}
    save = plotting.save_figure

    def keep(fig, path, **kwargs):
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        kept["figure"] = fig.bbox
        kept["labels"] = [ax.yaxis.label.get_window_extent(renderer) for ax in fig.axes]
        kept["ticks"] = [  # the drawn ones: beside the axes (the axis holds labels beyond its limits too)
            [
                box
                for box in (t.get_window_extent(renderer) for t in ax.get_yticklabels() if t.get_text())
                if ax.bbox.y0 <= 0.5 * (box.y0 + box.y1) <= ax.bbox.y1
            ]
            for ax in fig.axes
        ]
        kept["titles"] = [ax.title.get_window_extent(renderer) for ax in fig.axes if ax.get_title()]
        return save(fig, path, **kwargs)

    monkeypatch.setattr(plotting, "save_figure", keep)
    output.plot_family(family, tmp_path / "branch.png")
    assert (tmp_path / "branch.png").stat().st_size > 0
    return kept


@pytest.mark.parametrize("largest, amplitude", [(1.0, 1.0), (1e15, 30.0)])
def test_the_family_figure_keeps_its_labels_inside_and_apart(
    family, monkeypatch, tmp_path, largest, amplitude
):
    """Multipliers up to ``largest`` (tick labels up to "1e+15") and amplitudes scaled to two-digit
    ticks: the y labels, tick labels and title inside the figure, no y label over a tick label."""
    ob = family.branches[0]
    measures = dict(ob.measures)
    mu = measures["max_abs_multiplier"]
    measures["max_abs_multiplier"] = np.geomspace(0.5, largest, len(mu)) if largest > 1 else mu
    measures["A1"] = measures["A1"] * amplitude
    scaled = dataclasses.replace(family, branches=[dataclasses.replace(ob, measures=measures)])
    kept = _texts_of(scaled, monkeypatch, tmp_path)
    inside = kept["figure"]
    for box in [*kept["labels"], *kept["titles"], *(b for ticks in kept["ticks"] for b in ticks)]:
        assert inside.x0 <= box.x0 and box.x1 <= inside.x1 and inside.y0 <= box.y0 and box.y1 <= inside.y1
    for label, ticks in zip(kept["labels"], kept["ticks"]):
        assert ticks and all(label.x1 < tick.x0 for tick in ticks)
