"""The wall's own restitution kappa(v0), turning point d(v0) and clearance D(v0) (issue 20, item 1): the
interpolants against direct tighter contacts off their nodes, and the contact integration itself
against the closed forms of the conservative wall, the exact scaling of the Newtonian wall
(pbar = 0) and eq. (21)'s second-order gap where the dissipation is small."""

import numpy as np
import pytest
from scipy import special

from slosh_bif.model.restitution import (
    dissipation_at_unit_speed,
    kappa,
    simulate_rebound,
)
from slosh_bif.model.restitution.wall import contact, wall_law


@pytest.mark.parametrize("n, pbar", [(6, 2), (20, 2)])
def test_the_interpolant_matches_direct_tight_contacts_off_its_nodes_to_1e_8(n, pbar):
    law = wall_law(0.1, 0.2, n, pbar)
    assert max(law.kappa_error, law.depth_error, law.clearance_error) < 1e-8  # the measured error it states
    for v0 in (0.073, 1.37, 13.1):  # between nodes
        assert (
            abs(float(law.kappa(v0)) - simulate_rebound(v0, 0.1, 0.2, n, pbar, rtol=1e-13, atol=1e-15)) < 1e-8
        )


def test_the_conservative_wall_returns_every_speed_and_turns_where_eq_17_says():
    """And its equivalent rigid wall lies where the time spent in the wall puts it: the half
    contact lasts (d / v0) int_0^1 (1 - u^m)^(-1/2) du = (d / v0) B(1/m, 1/2) / m, m = 2n + 2."""
    for n in (6, 50):
        m = 2 * n + 2
        for v0 in (0.1, 1.0, 10.0):
            c = contact(v0, 0.0, 0.2, n, n)
            assert c.kappa == pytest.approx(1.0, abs=1e-10)
            d = ((n + 1) * v0**2 / 0.2) ** (1 / m)
            assert c.depth == pytest.approx(d, rel=1e-10)
            assert c.clearance == pytest.approx(d * special.beta(1 / m, 0.5) / m, rel=1e-10)


def test_the_newtonian_wall_is_scale_invariant():
    """pbar = 0: x -> s^(1/(n+1)) x, t -> s^(-n/(n+1)) t, v -> s v leaves the wall's equation as
    it is, so kappa is the same at every speed and d and D grow exactly like v0^(1/(n+1)): direct
    contacts at four speeds say so, and the law built from one contact and that scaling agrees
    with tighter direct contacts across its range (its stated error below 1e-12)."""
    for n in (6, 50):
        direct = [contact(v, 0.35, 0.2, n, 0, rtol=1e-13, atol=1e-15) for v in (0.06, 0.5, 4.0, 19.0)]
        assert np.ptp([c.kappa for c in direct]) < 1e-11
        for c in direct:
            assert c.depth / c.v0 ** (1 / (n + 1)) == pytest.approx(
                direct[1].depth / 0.5 ** (1 / (n + 1)), rel=1e-11
            )
            assert c.clearance / c.v0 ** (1 / (n + 1)) == pytest.approx(
                direct[1].clearance / 0.5 ** (1 / (n + 1)), rel=1e-11
            )
        law = wall_law(0.35, 0.2, n, 0)
        assert max(law.kappa_error, law.depth_error, law.clearance_error) < 1e-12
        for c in direct:
            assert float(law.kappa(c.v0)) == pytest.approx(c.kappa, abs=1e-12)
            assert float(law.depth(c.v0)) == pytest.approx(c.depth, rel=1e-12)
            assert float(law.clearance(c.v0)) == pytest.approx(c.clearance, rel=1e-12)
        assert float(law.kappa(1.0)) == pytest.approx(simulate_rebound(1.0, 0.35, 0.2, n, 0), abs=1e-9)


def test_eq_21_holds_to_second_order_where_the_dissipation_is_small():
    """kappa_wall - kappa_21 ~ (q/8) delta^2 (q = 2 + pbar/(n+1)): eq. (21) is first order."""
    lam, chi, n, pbar = 0.02, 0.2, 50, 2
    law = wall_law(lam, chi, n, pbar)
    for v0 in (0.2, 1.0, 5.0):
        delta = dissipation_at_unit_speed(lam, chi, n, pbar) * v0 ** (pbar / (n + 1))
        q = 2 + pbar / (n + 1)
        gap = float(law.kappa(v0)) - float(kappa(v0, lam, chi, n, pbar))
        assert gap == pytest.approx(q / 8 * delta**2, rel=0.2), (v0, gap, delta)


def test_bad_walls_and_speeds_are_one_line_errors():
    with pytest.raises(ValueError, match="chi"):
        wall_law(0.1, 0.0, 6, 0)
    with pytest.raises(ValueError, match="pbar"):
        wall_law(0.1, 0.2, 6, 1)
    with pytest.raises(ValueError, match="v_min < v_max"):
        wall_law(0.1, 0.2, 6, 0, 2.0, 1.0)
    with pytest.raises(ValueError, match="outside the measured range"):
        wall_law(0.1, 0.2, 6, 0).kappa(100.0)
