"""Synthetic shaking-table measurements of a tank, for the worked example of `slosh-bif fit` in Hz
and metres (docs/findings/identify.md): the README's tank (a 10 m water cylinder filled to 8 m)
on a heavier 0.8 Hz support (4,000 t, damping ratio 0.01) under a ground acceleration of 2 m/s^2,
swept over 0.60-0.86 Hz. At each frequency the parameters are the tank's there (``tank_model``:
sigma, gamma and Abar move with the frequency), the response is the stable 2pi-orbit of the full
model (9) found by shooting from the slow flow's steady state, its first harmonic A1 in metres,
and Gaussian noise of 1 % of the largest (seeded) is added, with that std written beside it.
Frequencies where that orbit of (9) is unstable (near the resonance: the response there is not
periodic) are left out, as a periodic fit could not use them; the script names them.

    python examples/fit_tank_response.py --out docs/identify/tank
    slosh-bif fit --params docs/identify/tank/tank.toml --data docs/identify/tank/measured.csv \
        --free lam,gamma --set lam=0.5 --set gamma=0.3 --model smooth --out docs/identify/tank/fit-smooth
"""

from __future__ import annotations

import argparse
import dataclasses
import warnings
from pathlib import Path

import numpy as np

from slosh_bif.identify.response_model import response_curve
from slosh_bif.model.parameter_file import render_parameter_file
from slosh_bif.model.tank import Site, Tank, tank_model
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import orbit_from_slow_flow

TANK = Tank("cylinder", depth=8.0, radius=5.0)
SITE = Site(
    structure_mass=4.0e6,
    structure_frequency=0.8,
    excitation_frequency=0.72,
    ground_acceleration=2.0,
    clearance=1.0,
    damping_ratio=0.01,
)
FREQUENCIES = np.linspace(0.60, 0.86, 14)  # Hz


def measured_amplitude(frequency: float) -> float | None:
    """A1 (metres) of the stable 2pi-orbit of (9) at ``frequency``, from the slow flow's state;
    None where that orbit is unstable."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = tank_model(TANK, dataclasses.replace(SITE, excitation_frequency=frequency)).params
        stable = [a for a, ok in response_curve(params).states_at(params.sigma) if ok]
    orbit = orbit_from_slow_flow(params, max(stable))
    if not (orbit.converged and orbit.stable):
        return None
    problem = ShootingProblem(params, segments=4)
    x = problem.initial_states(orbit.y0, params.sigma)
    return orbit_measures(problem, x, params.sigma)["A1"] * SITE.clearance


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="folder for tank.toml and measured.csv")
    parser.add_argument("--seed", type=int, default=0, help="seed of the noise (default 0)")
    parser.add_argument(
        "--noise", type=float, default=0.01, help="noise, a fraction of the largest amplitude"
    )
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    table = {**dataclasses.asdict(TANK), **dataclasses.asdict(SITE)}
    (args.out / "tank.toml").write_text(
        render_parameter_file(tank=table, comment="the tank of examples/fit_tank_response.py (SI units)")
    )
    found = [(f, measured_amplitude(f)) for f in FREQUENCIES]
    left = [f"{f:.3f}" for f, a in found if a is None]
    if left:
        print(f"left out (the orbit of (9) there is unstable or not found): {', '.join(left)} Hz")
    frequencies = np.array([f for f, a in found if a is not None])
    A = np.array([a for _, a in found if a is not None])
    size = args.noise * A.max()
    noisy = A + np.random.default_rng(args.seed).normal(0.0, size, A.size)
    rows = "".join(f"{f:.6f},{a:.6f},{size:.6f}\n" for f, a in zip(frequencies, noisy))
    (args.out / "measured.csv").write_text("f_hz,A_m,std_m\n" + rows)
    truth = tank_model(TANK, SITE).params
    print(
        f"wrote {args.out}/tank.toml and measured.csv: {len(A)} points, noise {size:.3g} m (seed "
        f"{args.seed}); truth at {SITE.excitation_frequency} Hz: lam = {truth.lam}, gamma = {truth.gamma:.6g}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
