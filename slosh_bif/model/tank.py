"""From a real tank to the model: the linear sloshing modes of an upright cylindrical or a
rectangular tank, and the map of a tank on a structure under harmonic ground motion to the
dimensionless parameters of eqs. (5)-(9).

Modes (linear potential flow, flat bottom, free surface; Abramson, NASA SP-106 (1966), ch. 6;
Dodge, "The new dynamic behavior of liquids in moving containers", SwRI (2000), ch. 3 and 4). Mode
k is the k-th sloshing mode antisymmetric in the excitation direction (the ones a horizontal motion
excites); h is the depth, g gravity, m_F the liquid's mass.

* cylinder of radius R: xi_k the k-th root of J1'(xi) = 0 (xi_1 = 1.8412), q_k = xi_k h / R,
  ``omega_k^2 = (g xi_k / R) tanh(q_k)``, ``m_k / m_F = 2 tanh(q_k) / (xi_k (xi_k^2 - 1) h / R)``;
* rectangle of length L along the motion: k_k = (2k - 1) pi / L, q_k = k_k h,
  ``omega_k^2 = g k_k tanh(q_k)``, ``m_k / m_F = 8 tanh(q_k) / ((2k - 1)^3 pi^3 h / L)``;
* the height of m_k above the bottom, from the moment of the wall pressure (bottom pressure
  excluded): ``H_k = h (1 - (cosh q_k - 1) / (q_k sinh q_k))``;
* the fixed ("inert") mass ``m_0 = m_F - sum_k m_k`` over all modes: the series is summed to
  ``SERIES_TERMS`` terms, and its rest, below ``R / (pi^3 h SERIES_TERMS^2)`` (cylinder), is added
  in its asymptotic form. In the shallow limit sum_k m_k -> m_F (sum 2/(xi_k^2 - 1) = 1 and
  sum 8/(pi^2 (2k-1)^2) = 1); in the deep limit m_k -> 0, m_0 -> m_F (the paper's Fig. 4).

The map to the model (eqs. 5-7, read with their time scale set by the forcing, tau = Omega t,
which is how sigma enters (7)):

* the primary mass is the structure and the fixed liquid, ``M = M_s + m_0`` (the paper's
  ``M = m_0 + m_tank``); its stiffness ``k = M_s (2 pi f_s)^2`` from the structure's own natural
  frequency f_s (the empty tank on its support), ``omega^2 = k / M``; its damping ``c = 2 zeta_s M omega``;
* the particle is the first sloshing mode: ``m = m_1``, ``omega_1`` its frequency;
* ``eps = m / M``, ``beta = omega_1 / omega``, ``1 - eps sigma = omega^2 (1 + eps beta^2) / ((1 + eps)
  Omega^2)``
  with Omega = 2 pi f the excitation's angular frequency (the coefficient of X in (7));
* ``gamma = c / (eps M (1 + eps) Omega)``, the damping of (7) in tau exactly (the paper's (6) gives
  it with omega sqrt((1 + eps beta^2)/(1 + eps)) for Omega, i.e. without the factor sqrt(1 - eps sigma));
* lengths in units of the clearance D (the particle meets the walls at w = +-D, so |w| = 1);
* the ground motion of acceleration amplitude a_g enters (5) as the force its displacement
  ``Y = a_g / Omega^2`` transmits through the support spring, ``k Y cos(Omega t)``, on the primary
  mass only, as in (5); then ``eps Abar = k a_g / (M Omega^4 D)``.

The wall's law (lam, chi, n, pbar) is not given by linear theory: it stays an input, with the
paper's values (Figs. 9-15) as defaults.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from slosh_bif.model.params import Params
from slosh_bif.model.presets import get_preset

__all__ = [
    "Modes",
    "cylinder_modes",
    "rectangle_modes",
    "Tank",
    "Site",
    "TankModel",
    "tank_model",
    "check_wall",
    "SERIES_TERMS",
    "ModelValidityWarning",
]

SERIES_TERMS = 400
GRAVITY = 9.80665  # m/s^2, standard gravity
# The paper's wall (Figs. 9, 10, 13-15), read from the presets, where the paper's values live.
WALL_DEFAULTS = {name: getattr(get_preset("fig10").params, name) for name in ("lam", "chi", "n", "pbar")}


class ModelValidityWarning(UserWarning):
    """A tank whose dimensionless parameters leave the range where the model's analysis holds."""


@dataclasses.dataclass(frozen=True)
class Modes:
    """The first modes of a tank: ``omega`` (rad/s), ``mass_ratio`` m_k / m_F, ``height`` of m_k
    above the bottom (m), and ``fixed_ratio`` m_0 / m_F (all modes summed)."""

    omega: np.ndarray
    mass_ratio: np.ndarray
    height: np.ndarray
    fixed_ratio: float


def _positive(**values):
    for name, value in values.items():
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive finite number; got {value!r}")


def _heights(q, depth):
    # q sinh q overflows beyond q ~ 700, where the ratio is 1/q to rounding
    ratio = np.where(q < 700, (np.cosh(np.minimum(q, 700)) - 1) / (q * np.sinh(np.minimum(q, 700))), 1 / q)
    return depth * (1 - ratio)


def _shallow_limit(q_last, depth, span: str, size: float):
    """A one-line error when the tank is too shallow for the series: its tail is summed with
    tanh q = 1, which needs q >= 3 at the last term (tanh 3 = 0.995)."""
    if q_last < 3.0:
        least = depth * 3.0 / q_last
        raise ValueError(
            f"depth / {span} = {depth / size:.3g} is too shallow for the sloshing-mode series: the "
            f"depth must be at least {least:.3g} m for this {span}"
        )


def _modes(omega2, ratio_all, q, depth, modes, tail):
    fixed = 1.0 - float(np.sum(ratio_all)) - tail
    return Modes(np.sqrt(omega2[:modes]), ratio_all[:modes].copy(), _heights(q[:modes], depth), fixed)


def cylinder_modes(radius: float, depth: float, *, modes: int = 3, gravity: float = GRAVITY) -> Modes:
    """The first ``modes`` antisymmetric sloshing modes of an upright circular cylinder."""
    from scipy.special import jnp_zeros

    _positive(radius=radius, depth=depth, gravity=gravity)
    xi = jnp_zeros(1, SERIES_TERMS)
    q = xi * depth / radius
    _shallow_limit(q[-1], depth, "radius", radius)
    ratio = 2 * np.tanh(q) / (xi * (xi**2 - 1) * depth / radius)
    # The rest of the series: xi_k ~ (k - 1/4) pi and tanh -> 1, so m_k / m_F ~ 2 R / (h pi^3 (k - 1/4)^3).
    tail = 2 * radius / (depth * math.pi**3) * _cubic_tail(SERIES_TERMS + 0.75)
    return _modes(gravity * xi / radius * np.tanh(q), ratio, q, depth, _count(modes), tail)


def rectangle_modes(length: float, depth: float, *, modes: int = 3, gravity: float = GRAVITY) -> Modes:
    """The first ``modes`` antisymmetric sloshing modes of a rectangular tank of ``length`` along the
    motion."""
    _positive(length=length, depth=depth, gravity=gravity)
    odd = 2 * np.arange(1, SERIES_TERMS + 1) - 1.0
    wavenumber = odd * math.pi / length
    q = wavenumber * depth
    _shallow_limit(q[-1], depth, "length", length)
    ratio = 8 * np.tanh(q) / (odd**3 * math.pi**3 * depth / length)
    tail = 8 * length / (depth * math.pi**3) * _cubic_tail(2 * SERIES_TERMS + 1, step=2)
    return _modes(gravity * wavenumber * np.tanh(q), ratio, q, depth, _count(modes), tail)


def _cubic_tail(start: float, step: float = 1.0) -> float:
    """sum over j >= 0 of (start + j step)^-3, by the Euler-Maclaurin formula (exact to 1e-12 here)."""
    return 1 / (2 * step * start**2) + 1 / (2 * start**3) + 3 * step / (12 * start**4)


def _count(modes):
    if not (isinstance(modes, int) and 1 <= modes <= SERIES_TERMS):
        raise ValueError(f"modes must be an integer in [1, {SERIES_TERMS}]; got {modes!r}")
    return modes


@dataclasses.dataclass(frozen=True)
class Tank:
    """An upright tank: ``shape`` "cylinder" (``radius``) or "rectangle" (``length`` along the
    motion, ``width`` across it), liquid ``depth``, ``density`` (kg/m^3), optional closed ``height``
    (the depth must not exceed it). SI units."""

    shape: str
    depth: float
    radius: float | None = None
    length: float | None = None
    width: float | None = None
    density: float = 1000.0
    height: float | None = None

    def __post_init__(self):
        if self.shape not in ("cylinder", "rectangle"):
            raise ValueError(f"shape must be 'cylinder' or 'rectangle'; got {self.shape!r}")
        need = ("radius",) if self.shape == "cylinder" else ("length", "width")
        _positive(depth=self.depth, density=self.density, **{name: getattr(self, name) for name in need})
        if self.height is not None:
            _positive(height=self.height)
            if self.depth > self.height:
                raise ValueError(f"depth {self.depth:g} m exceeds the tank's height {self.height:g} m")

    @property
    def liquid_mass(self) -> float:
        area = math.pi * self.radius**2 if self.shape == "cylinder" else self.length * self.width
        return self.density * area * self.depth

    def modes(self, count: int = 3, gravity: float = GRAVITY) -> Modes:
        if self.shape == "cylinder":
            return cylinder_modes(self.radius, self.depth, modes=count, gravity=gravity)
        return rectangle_modes(self.length, self.depth, modes=count, gravity=gravity)


@dataclasses.dataclass(frozen=True)
class Site:
    """The structure the tank stands on and the ground motion: ``structure_mass`` (kg, the empty
    tank and its support), ``structure_frequency`` (Hz, their own natural frequency), ``damping_ratio``,
    ``excitation_frequency`` (Hz), ``ground_acceleration`` (m/s^2, amplitude) and the ``clearance``
    (m) the first mode's mass travels before the liquid hits the wall (the length unit)."""

    structure_mass: float
    structure_frequency: float
    excitation_frequency: float
    ground_acceleration: float
    clearance: float
    damping_ratio: float = 0.02

    def __post_init__(self):
        _positive(
            structure_mass=self.structure_mass,
            structure_frequency=self.structure_frequency,
            excitation_frequency=self.excitation_frequency,
            ground_acceleration=self.ground_acceleration,
            clearance=self.clearance,
        )
        if not (math.isfinite(self.damping_ratio) and 0 <= self.damping_ratio < 1):
            raise ValueError(f"damping_ratio must be in [0, 1); got {self.damping_ratio!r}")


@dataclasses.dataclass(frozen=True)
class TankModel:
    """A tank on its site as the model: ``params``, the ``modes`` and ``rows`` (quantity, value,
    unit, where its formula comes from) for a table."""

    params: Params
    modes: Modes
    rows: tuple


def check_wall(wall: dict | None) -> dict:
    """The wall's law (lam, chi, n, pbar: the paper's values where ``wall`` has none), checked by
    :class:`Params` (ranges, a real restitution coefficient): a one-line error before any work."""
    unknown = sorted(set(wall or {}) - set(WALL_DEFAULTS))
    if unknown:
        raise ValueError(
            f"unknown wall parameter {unknown[0]!r}; the wall's law is {', '.join(WALL_DEFAULTS)}"
        )
    law = {**WALL_DEFAULTS, **(wall or {})}
    Params(eps=0.05, beta=0.0, gamma=0.0, sigma=0.0, Abar=0.0, **law)  # only the wall's fields matter here
    return law


def tank_model(tank: Tank, site: Site, *, wall: dict | None = None, gravity: float = GRAVITY) -> TankModel:
    """The parameters of (9) for ``tank`` on ``site`` (see the module docstring for every formula);
    ``wall`` overrides the paper's lam, chi, n, pbar. Warns (:class:`ModelValidityWarning`) where
    eps or sigma leave the model's range."""
    law = check_wall(wall)
    modes = tank.modes(3, gravity)
    m_F = tank.liquid_mass
    m_0, m_1 = modes.fixed_ratio * m_F, modes.mass_ratio[0] * m_F
    M = site.structure_mass + m_0
    k = site.structure_mass * (2 * math.pi * site.structure_frequency) ** 2
    omega, omega_1, Omega = math.sqrt(k / M), float(modes.omega[0]), 2 * math.pi * site.excitation_frequency
    eps, beta = m_1 / M, omega_1 / omega
    sigma = (1 - omega**2 * (1 + eps * beta**2) / ((1 + eps) * Omega**2)) / eps
    gamma = 2 * site.damping_ratio * omega / (eps * (1 + eps) * Omega)
    abar = k * site.ground_acceleration / (eps * M * Omega**4 * site.clearance)
    params = Params(eps=eps, beta=beta, gamma=gamma, sigma=sigma, Abar=abar, **law)
    if eps > 0.1:
        warnings.warn(
            f"eps = {eps:.3g} > 0.1: the multiple-scales analysis assumes a small sloshing mass m_1 / M",
            ModelValidityWarning,
            stacklevel=2,
        )
    if abs(eps * sigma) > 0.5:
        warnings.warn(
            f"eps sigma = {eps * sigma:.3g}: the forcing is far from 1:1 resonance with the vessel "
            "(the model assumes |Omega - omega| = O(eps))",
            ModelValidityWarning,
            stacklevel=2,
        )
    source = (
        "Abramson (1966) ch. 6; Dodge (2000) ch. 3"
        if tank.shape == "cylinder"
        else "Abramson (1966) ch. 6; Dodge (2000) ch. 4"
    )
    rows = (
        ("liquid mass m_F", m_F, "kg", "density x volume"),
        ("first sloshing mass m_1", m_1, "kg", source),
        ("fixed liquid mass m_0", m_0, "kg", source + " (m_F minus all modes)"),
        ("height of m_1 above the bottom", float(modes.height[0]), "m", "moment of the wall pressure"),
        ("sloshing frequency f_1", omega_1 / (2 * math.pi), "Hz", source),
        ("primary mass M = M_s + m_0", M, "kg", "paper, Sec. 3: M = m_0 + m_tank"),
        ("vessel frequency f = sqrt(k/M)/(2 pi)", omega / (2 * math.pi), "Hz", "k = M_s (2 pi f_s)^2"),
        ("eps = m_1 / M", eps, "", "eq. (5)"),
        ("beta = omega_1 / omega", beta, "", "eq. (6)"),
        ("sigma", sigma, "", "eq. (7): 1 - eps sigma = omega^2 (1 + eps beta^2) / ((1 + eps) Omega^2)"),
        ("gamma", gamma, "", "eq. (7): c / (eps M (1 + eps) Omega), c = 2 zeta_s M omega"),
        ("Abar", abar, "", "eq. (7): eps Abar = k a_g / (M Omega^4 D)"),
    )
    return TankModel(params, modes, rows)
