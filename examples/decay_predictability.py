"""How far a free decay of the full models can be predicted from its start: the Fig. 10 set with
the forcing off, the vessel released at X = 3 with the particle in the middle at rest (the start
of examples/free_decay.py), integrated by (9) and by (8) with lam and with lam (1 + d) for
relative changes d from 1e-6 to 5e-2. Printed: the largest difference of the vessel's amplitude
|X + i X'| averaged over windows of 40 time units, before and after tau = 100. Where a change of
1e-6 moves the average as much as one of 5e-2, the record beyond that time says nothing about lam
in a trajectory fit by the full model (docs/findings/identify.md).

    python examples/decay_predictability.py
"""

from __future__ import annotations

import numpy as np

from slosh_bif import get_preset
from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.flows.smooth.integrator import integrate_grid

STEP, LENGTH, WINDOW, SPLIT = 0.05, 400.0, 40.0, 100.0
CHANGES = (1e-6, 1e-4, 1e-2, 5e-2)


def amplitude(params, model: str, tau) -> np.ndarray:
    """|X + i X'| along ``tau`` from the released vessel, by (9) or by (8)."""
    y0 = np.array([3.0, 0.0, 0.0, 0.0])
    if model == "(9)":
        y = integrate_grid(params, y0, tau)
        return np.hypot(y[:, 0], y[:, 1])
    t, y, _, code = ImpactFlow(params, STEP).run(y0, 0.0, tau[-1], stick_speed=1e-9, max_impacts=10**6)
    if code != 0:
        raise SystemExit(f"the simulation of (8) stopped early (code {code})")
    return np.hypot(np.interp(tau, t, y[0]), np.interp(tau, t, y[1]))


def main() -> int:
    params = get_preset("fig10").params.replace(Abar=0.0)
    tau = np.arange(0.0, LENGTH, STEP)
    per = int(WINDOW / STEP)
    windows = np.arange(len(tau) // per) * WINDOW
    print(f"largest change of the {WINDOW:g}-window mean of |X + i X'| (before | after tau = {SPLIT:g})")
    for model in ("(9)", "(8)"):
        base = amplitude(params, model, tau)
        for d in CHANGES:
            other = amplitude(params.replace(lam=params.lam * (1 + d)), model, tau)
            diff = np.abs((other - base)[: len(windows) * per].reshape(-1, per).mean(axis=1))
            early, late = diff[windows + WINDOW <= SPLIT].max(), diff[windows >= SPLIT].max()
            print(f"{model} lam x (1 + {d:g}): {early:.2e} | {late:.2e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
