"""Timing in one process, and the first harmonic every frequency-response answer is read as."""

from __future__ import annotations

import statistics
import time

import numpy as np
from scipy.interpolate import CubicSpline

PERIOD = 2 * np.pi


def timed(fn, repeats: int = 3, min_seconds: float = 0.02, budget: float = 20.0):
    """(median seconds per call, last result, rounds run) over up to ``repeats`` rounds.

    A round repeats a fast call until it has run ``min_seconds`` (sub-millisecond calls are not
    timer noise then); rounds stop early once ``budget`` seconds are spent (slow methods get fewer).
    """
    times, result, spent = [], None, 0.0
    for _ in range(max(1, repeats)):
        calls, start = 0, time.perf_counter()
        while True:
            result = fn()
            calls += 1
            elapsed = time.perf_counter() - start
            if elapsed >= min_seconds:
                break
        times.append(elapsed / calls)
        spent += elapsed
        if spent >= budget:
            break
    return statistics.median(times), result, len(times)


def first_harmonic(t, X, periods: int = 20) -> float:
    """Amplitude of the e^{i tau} component of X over the last ``periods`` forcing periods."""
    t, X = np.asarray(t, dtype=float), np.asarray(X, dtype=float)
    if t[-1] - t[0] < periods * PERIOD * (1 - 1e-9):
        raise ValueError(
            f"need at least {periods} forcing periods of samples; got {(t[-1] - t[0]) / PERIOD:.3g}"
        )
    keep = t >= t[-1] - periods * PERIOD - 4 * (t[1] - t[0])
    grid = np.linspace(t[-1] - periods * PERIOD, t[-1], 256 * periods, endpoint=False)
    # A cubic spline, not linear interpolation: the latter's h^2 error is 3e-5 at the default samples.
    return float(abs(np.mean(CubicSpline(t[keep], X[keep])(grid) * np.exp(-1j * grid))) * 2)
