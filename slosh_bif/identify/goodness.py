"""Whether a fitted model describes the data it was fitted to, said out loud.

With each point's standard deviation given, the residuals divided by it are standard normal where
the model is right, and the misfit is chi-square with N - k degrees of freedom (k fitted
parameters): its upper tail probability is the fit's p-value. Without a std the scale is
estimated from the same residuals, so their size says nothing; their structure does: the signs of
the residuals along sigma (a Wald-Wolfowitz runs test within each sweep, along time for a record
in time: a model that is wrong leaves long runs of one sign), and an up-sweep against a
down-sweep at the same sigmas (a paired t test: both measured the same response, or the fit
compares one of them with the wrong one). The
tests' p-values are combined by Bonferroni's bound. Below :data:`THRESHOLD` the fit's intervals are
conditional on a model that does not describe the data, and the fit says so.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import stats

__all__ = ["THRESHOLD", "Goodness", "goodness", "runs_test", "sweep_test"]

THRESHOLD = 1e-3  # below this p-value the fitted model does not describe the data


@dataclasses.dataclass(frozen=True)
class Goodness:
    """``p_value`` of the fit (chi-square's tail with the std given, else the residuals' structure's,
    Bonferroni-combined), whether the model ``describes`` the data (p >= THRESHOLD), the plain
    ``statement`` where it does not (else ""), the estimated ``noise`` (the residuals' rms over
    the degrees of freedom, in the data's units when no std is given) and each test's p."""

    p_value: float
    describes: bool
    statement: str
    noise: float
    tests: dict

    def as_dict(self) -> dict:
        return {
            "p_value": self.p_value,
            "describes_the_data": self.describes,
            "statement": self.statement,
            "estimated_noise": self.noise,
            "tests": self.tests,
        }


def runs_test(r, groups) -> float:
    """One-sided p-value of too few runs of one sign in the residuals ``r`` taken in the order of
    ``groups`` (lists of indices, each a sweep ordered by sigma), the runs' counts and their
    expectations summed over the groups (the normal approximation); 1 with too few points."""
    count = mean = var = 0.0
    for group in groups:
        signs = np.sign(np.asarray(r, dtype=float)[list(group)])
        signs = signs[signs != 0]
        n1, n2 = int(np.sum(signs > 0)), int(np.sum(signs < 0))
        if n1 == 0 or n2 == 0 or n1 + n2 < 3:
            continue
        n = n1 + n2
        count += 1 + int(np.count_nonzero(np.diff(signs)))
        mean += 2.0 * n1 * n2 / n + 1.0
        var += 2.0 * n1 * n2 * (2.0 * n1 * n2 - n) / (n * n * (n - 1))
    if var <= 0:
        return 1.0
    return float(stats.norm.cdf((count - mean) / math.sqrt(var)))


def sweep_test(data, r) -> float:
    """Two-sided p-value of a paired t test between the up- and the down-sweep's residuals at the
    sigmas both measured (to 1e-9); 1 with fewer than three such pairs."""
    sweep = data.sweep or ("",) * len(data)
    up = {round(float(s), 9): k for k, s in enumerate(data.sigma) if sweep[k] == "up"}
    pairs = [
        (up[key], k)
        for k, s in enumerate(data.sigma)
        if sweep[k] == "down" and (key := round(float(s), 9)) in up
    ]
    if len(pairs) < 3:
        return 1.0
    d = np.array([r[a] - r[b] for a, b in pairs])
    if np.std(d) == 0.0:  # no spread: equal residuals say nothing, a constant shift everything
        return 1.0 if d[0] == 0.0 else 0.0
    return float(stats.ttest_1samp(d, 0.0).pvalue)


def _groups(data) -> list:
    """Each sweep's points (and the points without one) ordered by sigma; a record in time (no
    sigma): its points in time order."""
    if not hasattr(data, "sigma"):
        return [list(range(len(data)))]
    sweep = data.sweep or ("",) * len(data)
    return [
        sorted((k for k in range(len(data)) if sweep[k] == direction), key=lambda k: data.sigma[k])
        for direction in ("", "up", "down")
    ]


def goodness(data, r, free: int, model_name: str) -> Goodness:
    """Whether the model named ``model_name``, fitted with ``free`` parameters, describes ``data``
    given its residuals ``r`` at the estimate (divided by the std where the data give one)."""
    r = np.asarray(r, dtype=float)
    dof = max(len(r) - free, 1)
    rss = float(r @ r)
    noise = math.sqrt(rss / dof)
    if data.std is not None:
        p = float(stats.chi2.sf(rss, dof))
        tests = {"chi_square": p}
        detail = f"chi-square {rss:.4g} for {dof} degrees of freedom (p = {p:.2g})"
    else:
        tests = {"runs_of_one_sign": runs_test(r, _groups(data))}
        if hasattr(data, "sweep"):
            tests["up_against_down_sweep"] = sweep_test(data, r)
        p = min(1.0, len(tests) * min(tests.values()))
        parts = []
        along = "sigma" if hasattr(data, "sigma") else "time"
        if tests["runs_of_one_sign"] < THRESHOLD:
            parts.append(f"long runs of one sign along {along} (p = {tests['runs_of_one_sign']:.2g})")
        if tests.get("up_against_down_sweep", 1.0) < THRESHOLD:
            p_sweeps = tests["up_against_down_sweep"]
            parts.append(f"the up- and the down-sweep differ at equal sigmas (p = {p_sweeps:.2g})")
        detail = f"the residuals are structured: {'; '.join(parts)}; estimated noise {noise:.3g}"
    describes = p >= THRESHOLD
    statement = "" if describes else f"{model_name} as fitted does not describe these data: {detail}"
    return Goodness(p, describes, statement, noise, tests)
