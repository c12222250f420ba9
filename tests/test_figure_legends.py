"""Figures say what they draw: a legend lists only the line styles and special points drawn, and
markers of one kind that would stack are drawn once and counted."""

import numpy as np
import pytest

import slosh_bif as sb
import slosh_bif.report.plotting as plotting
from slosh_bif.report.plotting import mark_special, pyplot
from slosh_bif.slowflow.output import plot_frc
from slosh_bif.slowflow.steady_states import frequency_response


@pytest.fixture
def drawn_figures(monkeypatch):
    """The figures the plot functions hand to ``save_figure``, kept open instead of written."""
    figures = []

    def keep(fig, path, **_):
        figures.append(fig)
        return path

    monkeypatch.setattr(plotting, "save_figure", keep)
    yield figures
    for fig in figures:
        pyplot().close(fig)


def _legend(fig) -> list:
    return [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_an_all_stable_response_lists_no_unstable_line_and_names_its_ends(drawn_figures, tmp_path):
    fr = frequency_response(sb.get_preset("fig10").params, sigma_min=2.0, sigma_max=6.0)
    assert all(b.stable.all() for b in fr.branches)  # the case: no unstable run is drawn
    plot_frc(fr, tmp_path / "frc.png")
    labels = _legend(drawn_figures[0])
    assert "stable" in labels and "unstable" not in labels
    assert "end" in labels  # END markers are drawn at the range's ends
    assert not any(name in labels for name in ("fold (LP)", "period doubling (PD)", "Neimark-Sacker (NS)"))


def test_the_whole_response_lists_what_it_draws(drawn_figures, tmp_path):
    fr = frequency_response(sb.get_preset("fig10").params)
    kinds = {s.kind for b in fr.branches for s in b.special}
    plot_frc(fr, tmp_path / "frc.png")
    labels = _legend(drawn_figures[0])
    assert {"stable", "unstable", "fold (LP)", "end"} <= set(labels)
    assert ("period doubling (PD)" in labels) == ("PD" in kinds)


def test_markers_of_one_kind_that_would_stack_are_drawn_once_and_counted():
    fig, ax = pyplot().subplots(figsize=(6, 4))
    ax.plot([-6, 8], [0, 5])
    near = [(1.0 + 1e-4 * k, 2.0, "NS") for k in range(4)]
    far = [(-4.0, 1.0, "NS"), (1.0, 2.0, "LP")]  # another NS far away, and a fold at the cluster
    mark_special(ax, near + far)
    markers = [line for line in ax.lines if line.get_marker() not in ("None", None, "")]
    assert len(markers) == 3  # the four NS as one, the far NS, the LP
    texts = sorted(t.get_text() for t in ax.texts)
    assert "NS \u00d74" in texts
    assert np.count_nonzero([t == "NS" for t in texts]) == 1
    pyplot().close(fig)
