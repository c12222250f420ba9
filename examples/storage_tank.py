"""A real tank to the model and back to a design answer: a water tank of 10 m diameter filled to 8 m,
on a support whose own natural frequency is 0.8 Hz, under a harmonic ground motion near the
vessel's resonance. Prints the dimensionless parameters (with each formula's source), then for three
ground accelerations compares the forcing with the slow flow's critical forcing Abar_b of eq. (46)
and asks the lightest adequate model (`answer`, the ladder) whether the response from rest is
non-resonant, strongly modulated or periodic. Writes the parameter file that every command takes
with --params. Copy and edit TANK and SITE.

Usage: python examples/storage_tank.py [OUT_DIR]       (a few seconds)
"""

import sys
import warnings
from pathlib import Path

from slosh_bif.model.parameter_file import render_parameter_file
from slosh_bif.model.presets import state_from_uv
from slosh_bif.model.tank import Site, Tank, tank_model
from slosh_bif.slowflow.critical import critical_forcing
from slosh_bif.studies.ladder import answer

TANK = Tank("cylinder", depth=8.0, radius=5.0, density=1000.0)  # 628 t of water
SITE = Site(
    structure_mass=2.0e6,  # kg: the empty tank and its support
    structure_frequency=0.8,  # Hz: their own natural frequency
    excitation_frequency=0.72,  # Hz: the ground motion
    ground_acceleration=1.0,  # m/s^2: its amplitude (0.1 g); ACCELERATIONS below are tried too
    clearance=1.0,  # m: the sloshing mass's travel before the liquid hits the roof
    damping_ratio=0.02,
)


ACCELERATIONS = (0.5, 1.0, 1.5)  # m/s^2


def main(out=Path("results")):
    out.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = tank_model(TANK, SITE)
    for w in caught:
        print(f"warning: {w.message}")
    for quantity, value, unit, source in model.rows:
        print(f"{quantity:40s} {float(value):12.5g} {unit:3s}  {source}")
    P = model.params
    point = critical_forcing(P, P.sigma)
    print(
        f"\nthe slow flow's critical forcing at sigma = {P.sigma:.4g}: Abar_b = {point.Abar_b:.4g} "
        f"({point.kind})"
    )
    for a_g in ACCELERATIONS:  # Abar is proportional to the ground acceleration
        Q = P.replace(Abar=P.Abar * a_g / SITE.ground_acceleration)
        at_rest = state_from_uv(
            0.0, 0.0, 0.0, 0.0, eps=Q.eps
        )  # the tank and the liquid at rest when the motion starts
        result = answer("regime", Q, tol=0.05, state0=at_rest)
        side = "above" if Q.Abar > point.Abar_b else "below"
        print(
            f"a_g = {a_g:.2g} m/s^2: Abar = {Q.Abar:.4g} ({side} Abar_b); from rest: {result.result.regime} "
            f"({result.result.reason}), by the {result.model} in {result.seconds:.1f} s"
        )
    path = out / "storage_tank.toml"
    tank_table = {**vars(TANK), **vars(SITE)}
    path.write_text(render_parameter_file(tank=tank_table, comment="examples/storage_tank.py"))
    print(f"wrote {path}: slosh-bif chart --params {path} ... takes it")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results"))
