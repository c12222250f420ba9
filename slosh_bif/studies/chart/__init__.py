"""The chart of a full model's orbit bifurcations in two parameters: the curves of LP, PD, NS
and BP points traced from every such point of the orbit families, with their codimension-2
points, and the full model's critical forcing read off them beside the slow flow's Abar_b of
(46). One module per model (:mod:`~slosh_bif.studies.chart.smooth` for (9),
:mod:`~slosh_bif.studies.chart.impact` for (8) with its grazing curves) over the shared result,
curve tracing, critical forcing and output."""

from slosh_bif.lazy import lazy_names

# public name -> the module that defines it, loaded on first use
_WHERE = {
    "Chart": "result",
    "ChartSettings": "result",
    "check_box": "result",
    "chart_workers": "result",
    "bifurcation_chart": "smooth",
    "impact_chart": "impact",
    "CurveStart": "curves",
    "CurveFailure": "curves",
    "trace_curves": "curves",
    "critical_forcing_full": "critical",
    "FullCritical": "critical",
    "plot_chart": "output",
}

__all__ = sorted(_WHERE)


__getattr__, __dir__ = lazy_names(__name__, _WHERE)
