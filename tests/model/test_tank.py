"""From a real tank to the model (issue 21), against independent values: mpmath's Bessel zeros and
the series formulas evaluated in 40 digits (Abramson, NASA SP-106 (1966), ch. 6; Dodge, SwRI (2000),
ch. 3, eqs. for the upright cylinder: omega_n^2 = (g xi_n / R) tanh(xi_n h/R),
m_n/m_F = 2 tanh(xi_n h/R) / (xi_n (xi_n^2 - 1) h/R)), the limits of deep and shallow tanks, and the
physical system of eq. (5) against the model's linear part at the mapped parameters."""

import math
import warnings

import mpmath
import numpy as np
import pytest

from slosh_bif.model import tank as T
from slosh_bif.model._generated import models as gen

mpmath.mp.dps = 40


def _xi(k):
    return mpmath.besseljzero(1, k, derivative=1)


def test_first_roots_of_j1_prime_agree_with_mpmath():
    assert float(_xi(1)) == pytest.approx(1.8412, abs=5e-5)
    omega = T.cylinder_modes(1.0, 1.0, gravity=1.0).omega  # omega^2 = xi tanh(xi) at h = R = g = 1
    for k in (1, 2, 3):
        xi = _xi(k)
        assert omega[k - 1] ** 2 == pytest.approx(float(xi * mpmath.tanh(xi)), rel=1e-13)


@pytest.mark.parametrize("depth_ratio", [0.5, 2.0])
def test_first_mode_of_a_cylinder_against_the_series_formula_in_40_digits(depth_ratio):
    R, g = 5.0, 9.80665
    modes = T.cylinder_modes(R, depth_ratio * R)
    xi = _xi(1)
    q = xi * depth_ratio
    assert modes.mass_ratio[0] == pytest.approx(
        float(2 * mpmath.tanh(q) / (xi * (xi**2 - 1) * depth_ratio)), rel=1e-13
    )
    assert modes.omega[0] == pytest.approx(float(mpmath.sqrt(g * xi / R * mpmath.tanh(q))), rel=1e-13)


@pytest.mark.parametrize("depth_ratio", [0.05, 0.5, 2.0])
def test_modal_masses_and_the_fixed_mass_add_up_to_the_liquid(depth_ratio):
    # m_0 + m_1 + m_2 + m_3 = m_F minus the modes beyond the third, summed by mpmath to the end.
    modes = T.cylinder_modes(1.0, depth_ratio)
    rest = mpmath.nsum(
        lambda k: (
            2 * mpmath.tanh(_xi(int(k)) * depth_ratio) / (_xi(int(k)) * (_xi(int(k)) ** 2 - 1) * depth_ratio)
        ),
        [4, 60],
    )
    far = mpmath.nsum(
        lambda k: 2 / (depth_ratio * (mpmath.pi * (k - 0.25)) ** 3), [61, mpmath.inf]
    )  # xi_k ~ (k - 1/4) pi, tanh = 1
    assert modes.fixed_ratio + modes.mass_ratio.sum() == pytest.approx(1 - float(rest + far), abs=1e-7)


def test_deep_and_shallow_limits():
    deep, shallow = T.cylinder_modes(1.0, 100.0), T.cylinder_modes(1.0, 0.01)
    assert deep.mass_ratio[0] < 0.005 and deep.fixed_ratio > 0.99  # the liquid moves with the tank
    assert shallow.fixed_ratio < 0.01 and shallow.mass_ratio[0] == pytest.approx(
        2 / (float(_xi(1)) ** 2 - 1), rel=1e-3
    )  # sum 2/(xi^2 - 1) = 1
    rect = T.rectangle_modes(1.0, 0.01)
    assert rect.fixed_ratio < 0.02 and rect.mass_ratio[0] == pytest.approx(
        8 / math.pi**2, rel=1e-3
    )  # sum 8/(pi^2 (2k-1)^2) = 1
    assert T.rectangle_modes(1.0, 50.0).fixed_ratio > 0.99
    # the modal mass sits at mid-depth in a shallow tank, near the surface in a deep one
    assert shallow.height[0] == pytest.approx(0.005, rel=1e-3) and deep.height[0] > 0.99 * 100.0


def _site(**changes):
    base = dict(
        structure_mass=2.0e6,
        structure_frequency=0.8,
        excitation_frequency=0.72,
        ground_acceleration=0.5,
        clearance=1.0,
        damping_ratio=0.02,
    )
    return T.Site(**{**base, **changes})


def test_the_model_has_the_physical_systems_frequencies_and_forced_response():
    # Eq. (5) in SI units: the vessel M (stiffness k, forced through its support by k Y cos(Omega t),
    # Y = a_g / Omega^2) and the sloshing mass m_1 (omega_1). The linear part of (9) at the mapped
    # parameters, in tau = Omega t and lengths of the clearance D, must have the frequencies
    # omega / Omega and omega_1 / Omega and the undamped forced response u = kY / (k - M Omega^2).
    tank, site = T.Tank("cylinder", depth=8.0, radius=5.0), _site()
    model = T.tank_model(tank, site)
    P = model.params
    m_0 = model.modes.fixed_ratio * tank.liquid_mass
    M = site.structure_mass + m_0
    k = site.structure_mass * (2 * math.pi * site.structure_frequency) ** 2
    Omega = 2 * math.pi * site.excitation_frequency
    omega, omega_1 = math.sqrt(k / M), model.modes.omega[0]
    J = gen.smooth_jac(0.0, np.zeros(4), P.eps, P.beta, 0.0, P.sigma, 0.0, 0.0, P.chi, P.n, P.p)
    K = -J[np.ix_([1, 3], [0, 2])]  # the stiffness of (X, w)
    assert np.sort(np.linalg.eigvals(K).real) == pytest.approx(
        np.sort([(omega / Omega) ** 2, (omega_1 / Omega) ** 2]), rel=1e-12
    )
    X, w = np.linalg.solve(K - np.eye(2), [P.eps * P.Abar, P.eps * P.Abar])
    Y = site.ground_acceleration / Omega**2
    assert (X + P.eps * w) / (1 + P.eps) * site.clearance == pytest.approx(
        k * Y / (k - M * Omega**2), rel=1e-12
    )
    assert (X - w) / (1 + P.eps) == pytest.approx(0.0, abs=1e-12)  # the sloshing mass is not forced (eq. 5)
    assert P.eps == pytest.approx(model.modes.mass_ratio[0] * tank.liquid_mass / M, rel=1e-14)


def test_validity_warnings_and_bad_input():
    with pytest.warns(T.ModelValidityWarning, match="eps = .* > 0.1"):
        T.tank_model(T.Tank("cylinder", depth=8.0, radius=5.0), _site(structure_mass=1.0e5))
    with pytest.warns(T.ModelValidityWarning, match="far from 1:1 resonance"):
        T.tank_model(T.Tank("cylinder", depth=8.0, radius=5.0), _site(excitation_frequency=3.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        T.tank_model(
            T.Tank("rectangle", depth=2.0, length=6.0, width=3.0),
            _site(structure_mass=5e5, structure_frequency=1.0, excitation_frequency=0.95),
        )
    for make, says in [
        (lambda: T.Tank("cylinder", depth=8.0, radius=-5.0), "radius must be a positive finite number"),
        (
            lambda: T.Tank("cylinder", depth=8.0, radius=5.0, height=6.0),
            "depth 8 m exceeds the tank's height 6 m",
        ),
        (lambda: T.Tank("sphere", depth=1.0), "shape must be"),
        (lambda: T.Tank("rectangle", depth=1.0, length=2.0), "width must be a positive finite number"),
        (lambda: _site(clearance=0.0), "clearance must be a positive finite number"),
        (lambda: _site(damping_ratio=1.5), "damping_ratio must be in"),
        (lambda: T.cylinder_modes(1.0, 1.0, modes=0), "modes must be an integer"),
    ]:
        with pytest.raises(ValueError, match=says):
            make()
