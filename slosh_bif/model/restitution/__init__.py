"""The walls' restitution, in one folder: what an impact does as a function of its speed, and the
same on the slow invariant manifold as a function of the amplitude (eqs. 13-21, 31, 38-40).

* :mod:`~slosh_bif.model.restitution.eq21`: the paper's first-order law (21), (40), kappa on S+ (39)
  for one amplitude, and the rebound from the wall of (10) simulated directly;
* :mod:`~slosh_bif.model.restitution.wall`: the wall of (10) measured contact by contact, kappa(v0)
  and the clearance D(v0) as interpolants with stated errors;
* :mod:`~slosh_bif.model.restitution.on_manifold`: eq. (39) on S+ and where S+ ends;
* :mod:`~slosh_bif.model.restitution.corrected`: the measured wall on S+ (the corrected slow flow);
* :mod:`~slosh_bif.model.restitution.laws`: the two interfaces (:class:`SpeedLaw`,
  :class:`ManifoldRestitution`) and the factories :func:`speed_law`, :func:`manifold_law` that
  the rest of the package asks.

The names of :mod:`~slosh_bif.model.restitution.eq21` are importable from here as well
(``restitution.kappa(v0, lam, chi, n, pbar)``).
"""

from slosh_bif.model.restitution.eq21 import (
    Eq21Law,
    I,
    ManifoldKappa,
    dissipation_at_unit_speed,
    kappa,
    kappa_low,
    kappa_newtonian,
    kappa_on_manifold,
    rho,
    rho_unchecked,
    simulate_rebound,
)
from slosh_bif.model.restitution.eq39 import END_KINDS
from slosh_bif.model.restitution.laws import (
    MODELS,
    ManifoldRestitution,
    SpeedLaw,
    check_model,
    manifold_law,
    speed_law,
)

__all__ = [
    "I",
    "dissipation_at_unit_speed",
    "kappa",
    "kappa_newtonian",
    "rho",
    "rho_unchecked",
    "kappa_low",
    "kappa_on_manifold",
    "ManifoldKappa",
    "simulate_rebound",
    "Eq21Law",
    "SpeedLaw",
    "ManifoldRestitution",
    "MODELS",
    "check_model",
    "speed_law",
    "manifold_law",
    "END_KINDS",
]
