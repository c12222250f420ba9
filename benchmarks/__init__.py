"""Benchmarks of slosh_bif, kept beside the package as scipy keeps its own: work-precision charts
and speed ratios measured in one process (ratios, not seconds, are what carry over between
machines). They run from a source checkout.

* ``python -m benchmarks --out DIR`` (:func:`benchmarks.run.run`): the frequency-response question
  (:mod:`benchmarks.frequency_response`), the integration question (:mod:`benchmarks.integration`),
  the cost of growth (:mod:`benchmarks.growth`) and the speed targets (:mod:`benchmarks.speed`),
  each written as a CSV and a chart (:mod:`benchmarks.output`);
* ``python -m benchmarks.continuation``, ``python -m benchmarks.shooting``,
  ``python -m benchmarks.codim2``: continuation against a natural sweep, the shooting branch,
  curves in two parameters against a one-parameter branch.
"""
