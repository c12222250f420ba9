"""Work-precision benchmarks: what each method costs for the accuracy it gives.

Four questions, each measured in one process (medians of repeated runs; ratios, not seconds,
are what carry over between machines):

* **The frequency-response question** (:func:`frequency_response_bench`): the amplitude of X at a
  few detunings sigma of the Fig. 10 and Fig. 13 sets (first-harmonic amplitude A1 of X, as in
  ``slosh-bif compare``), answered by the eq. (46) continuation, by integrating the slow flow
  (45) to its steady state, by simulating the impact model (8) and the smooth model (9), and by
  shooting on (9). Error: the largest relative error over the sigmas against a reference orbit
  found by shooting at rtol 1e-12 (4 arcs) from a simulation that has settled on it (see
  :func:`settle_and_shoot`), checked stable, and
  whose own error is estimated by repeating it at rtol 1e-10.
* **The integration question** (:func:`integration_bench`): the state of (9) after one forcing
  period at n = 50 (Fig. 10 set) and n = 6 (Fig. 12 set), by every integrator the package offers
  (the compiled DOP853 and its scipy fallback) and scipy's ``solve_ivp`` methods on the Python
  right-hand side (the baseline a user would otherwise pick), against a compiled DOP853 run at
  rtol 1e-13; time and right-hand-side evaluations.
* **The cost of growth** (:func:`growth_bench`): time to trace a branch and to simulate a fixed
  interval as the wall exponent n grows, simulation time against interval length, and regime-map
  time against grid size and number of worker processes.
* **Speed** (:func:`~benchmarks.speed.speed_bench`): the shooting command as a whole process
  against 1,000 scipy periods, start-up, the shooting start (the targets of the speed issue).
* **Against an earlier commit** (:func:`~benchmarks.against.against_bench`): branches, the chart and
  the scan run by this tree and by an earlier commit's, alternating; the ratio of their times.

:func:`run` writes each question's CSV and chart (:mod:`benchmarks.output`); the CLI is
``python -m benchmarks --out DIR``.
"""

from __future__ import annotations

from benchmarks import output as bench_output
from benchmarks.against import BASE, against_bench
from benchmarks.frequency_response import frequency_response_bench
from benchmarks.growth import growth_bench
from benchmarks.integration import integration_bench
from benchmarks.speed import speed_bench

__all__ = ["QUESTIONS", "run"]

# --- all of it ---------------------------------------------------------------------------------------

QUESTIONS = ("frequency-response", "integration", "growth", "speed", "against")


def run(out, *, only=None, quick: bool = False, repeats: int = 3, progress=None, base: str = BASE) -> list:
    """Run the chosen questions (all but "against", an hour, by default) and write their CSVs and
    charts to ``out``; ``base``: the commit "against" measures this tree against."""
    only = list(only or QUESTIONS[:-1])
    unknown = [q for q in only if q not in QUESTIONS]
    if unknown:
        raise ValueError(f"unknown benchmark {unknown[0]!r}; choose from {', '.join(QUESTIONS)}")
    if not (isinstance(repeats, int) and repeats >= 1):
        raise ValueError(f"repeats must be an integer >= 1; got {repeats!r}")
    written = []
    if "integration" in only:
        written += bench_output.write_integration(
            integration_bench(quick=quick, repeats=repeats, progress=progress), out
        )
    if "frequency-response" in only:
        written += bench_output.write_frequency_response(
            *frequency_response_bench(quick=quick, repeats=repeats, progress=progress), out
        )
    if "growth" in only:
        written += bench_output.write_growth(
            growth_bench(quick=quick, repeats=repeats, progress=progress), out
        )
    if "speed" in only:
        written += bench_output.write_speed(speed_bench(quick=quick, progress=progress), out)
    if "against" in only:
        written += bench_output.write_against(against_bench(base=base, quick=quick, progress=progress), out)
    return written
