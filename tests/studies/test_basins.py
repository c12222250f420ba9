"""Basins of attraction (issue 18): at sigma = 3 on the Fig. 10 set the two members of a mirror
pair of stable asymmetric orbits coexist; every attractor the map names is checked with scipy's
integrator, not the code that found it."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.simulation.settings import Workers
from slosh_bif.studies.basins import basin_map
from slosh_bif.studies.basins_output import attractor_table


@pytest.fixture(scope="module")
def basins():
    P = get_preset("fig10").params.replace(sigma=3.0)
    return P, basin_map(P, np.linspace(-3, 3, 4), np.linspace(-1, 1, 3), workers=Workers(max_workers=2))


def test_each_orbit_attractor_is_a_stable_periodic_orbit_by_scipy(basins, scipy_flow, scipy_multipliers):
    P, bmap = basins
    assert bmap.status == "complete" and abs(sum(bmap.fractions().values()) - 1) < 1e-12
    assert len(bmap.orbits) >= 2  # the mirror pair
    for name, y0 in bmap.orbits.items():
        assert np.linalg.norm(scipy_flow(P, y0, 2 * np.pi)[0] - y0) < 1e-7, name
        assert np.max(np.abs(scipy_multipliers(P, y0))) < 1, name
    a, b = list(bmap.orbits.values())[:2]
    # Mirror images: the shift-reflection maps one orbit's state at tau = pi to minus the other's at 0.
    assert np.linalg.norm(scipy_flow(P, a, np.pi)[0] + b) < 1e-6


def test_bad_axes_are_one_line_errors_before_any_work():
    P = get_preset("fig10").params
    with pytest.raises(ValueError, match="axes must be two different names"):
        basin_map(P, [0.0], [0.0], axes=("X", "X"))
    with pytest.raises(ValueError, match="tmax must be finite"):
        basin_map(P, [0.0], [0.0], tmax=float("nan"))


def test_every_start_settles_and_the_shares_carry_their_uncertainty(basins):
    """Every start settles on one of the pair within the default bound (a strobe that stopped
    moving, not a fixed run length); the shares' bounds bracket the shares, and the chaotic early
    motion shows as uncertain cells at both perturbation sizes, with an exponent near 0."""
    P, bmap = basins
    assert set(bmap.label.ravel()) == set(bmap.orbits) and np.all(np.isfinite(bmap.periods))
    for name, (low, high) in bmap.fraction_bounds().items():
        assert low <= bmap.fractions()[name] == high
    assert sum(low for low, _ in bmap.fraction_bounds().values()) == pytest.approx(
        1 - np.mean(bmap.uncertain)
    )
    assert all(0 < f < 1 for f in bmap.uncertain_fraction.values())
    assert sorted(name.split(",")[0] for name in bmap.orbits) == ["asymmetric orbit a", "asymmetric orbit b"]


def test_the_basins_of_8_name_orbits_that_the_reference_flow_confirms():
    """basins --model impact: each orbit the map of (8) names is a fixed point of the 2pi map of the
    reference flow (scipy's expm between impacts, not the compiled flow that found it), stable by
    that map's finite-difference multipliers, and the pair are mirror images; a start on a wall at
    rest, pressed into it, is reported as sticking (where (8) is not defined), not as an orbit."""
    from slosh_bif import simulate_impact

    P = get_preset("fig10").params.replace(sigma=3.0)
    bmap = basin_map(
        P, np.linspace(-3, 3, 4), np.linspace(-1, 1, 3), model="impact", workers=Workers(max_workers=2)
    )
    assert bmap.status == "complete" and bmap.model == "impact" and len(bmap.orbits) >= 2

    def reference(y, t=2 * np.pi):
        return simulate_impact(P, y, (0.0, t), backend="scipy").y[:, -1]

    for name, y0 in bmap.orbits.items():
        assert np.linalg.norm(reference(y0) - y0) < 1e-8, name
        J = np.column_stack([(reference(y0 + 1e-6 * e) - reference(y0 - 1e-6 * e)) / 2e-6 for e in np.eye(4)])
        assert np.max(np.abs(np.linalg.eigvals(J))) < 1, name
    a, b = list(bmap.orbits.values())[:2]
    assert np.linalg.norm(reference(a, np.pi) + b) < 1e-6
    assert set(bmap.label[[0, -1]].ravel()) <= {"sticking"} | set(bmap.orbits)
    with pytest.raises(ValueError, match="model must be one of smooth, impact, impact-corrected"):
        basin_map(P, [0.0], [0.0], model="corrected")


def test_the_corrected_impact_models_basins_name_9s_mirror_pair(basins):
    """basins --model impact-corrected: the two orbits it names are (9)'s mirror pair (the orbits
    (9)'s own basin map names, found by shooting) up to the contact's duration, 1e-3 in A1."""
    P, smooth = basins
    bmap = basin_map(
        P,
        np.linspace(-3, 3, 4),
        np.linspace(-1, 1, 3),
        model="impact-corrected",
        workers=Workers(max_workers=2),
    )
    assert bmap.status == "complete" and bmap.model == "impact-corrected"
    named = [name for name in bmap.orbits if name.startswith("asymmetric orbit")]
    nine = [name for name in smooth.orbits if name.startswith("asymmetric orbit")]
    assert len(named) == 2 and len(nine) >= 1

    def a1(name):
        return float(name.split("A1 = ")[1])

    assert abs(a1(named[0]) - a1(nine[0])) < 1e-3 * a1(nine[0])


def test_uncertain_cells_of_unsettled_starts_are_not_read_as_fractal_boundaries():
    """A random set (seed 313) followed for 48 periods only: no start settles, and starts moved by
    1e-3 and 1e-6 of the plane end in another transient's regime. Those labels are not attractors,
    so the exponent of their changes is not read as the basins' boundary (it gave "fractal")."""
    P = get_preset("fig10").params.replace(
        eps=0.0518, beta=0.39, gamma=0.231, sigma=1.896, Abar=1.499, lam=0.108, chi=1.405, n=6, pbar=2
    )
    bmap = basin_map(
        P, np.linspace(-3, 3, 4), np.linspace(-1, 1, 3), tmax=300, workers=Workers(max_workers=1)
    )
    assert not np.isfinite(bmap.periods).any() and bmap.transient_uncertain == int(bmap.uncertain.sum()) > 0
    table = attractor_table(bmap)
    assert "uncertainty exponent not judged" in table
    assert "fractal" not in table and "smooth basin" not in table


def test_an_unsettled_start_of_the_corrected_impact_model_is_classified_from_its_own_state():
    """A random set (seed 300: n = 3, the measured wall's clearance 0.62 at unit speed) followed for
    48 periods: the starts that have not settled are simulated on from the state the strobe
    reached, in the contact band beyond D(v) (w = 1.36). That run refused it as a start outside the
    wall, and the whole map ended with exit 2; each cell now has its regime."""
    P = get_preset("fig10").params.replace(
        eps=0.0604, beta=0.19, gamma=0.163, sigma=3.026, Abar=3.376, lam=0.313, chi=1.421, n=3, pbar=3
    )
    bmap = basin_map(
        P,
        np.linspace(-3, 3, 3),
        np.linspace(-1, 1, 3),
        tmax=300,
        model="impact-corrected",
        workers=Workers(max_workers=1),
    )
    assert bmap.status == "complete"
    assert all(label.endswith("(not settled)") for label in bmap.label.ravel())
