"""The criticality of the orbit bifurcations of the vibro-impact model (8) and of the corrected
impact model against independent evaluations: the map's second and third derivatives (jets
through the exact flights and impacts) against central differences of the compiled flow's
saltation Jacobian and of the second derivative, the reset's generated derivatives against
differences of the reset, and each pitchfork's verdict and size law against the asymmetric
branch the package's switching finds without the coefficient."""

import math

import numpy as np
import pytest

from slosh_bif import get_preset, simulate_impact
from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.model._generated.impact_kernels import impact_reset_jet_kernel
from slosh_bif.orbits.impact.map_derivatives import ImpactMapDerivatives

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")

SETS = {
    "fig13 sigma=0.5": ("fig13", {"sigma": 0.5}),
    "pbar=2 wall": ("fig10", {"sigma": 3.0, "n": 20, "pbar": 2, "lam": 0.2}),
}


@pytest.fixture(scope="module", params=list(SETS))
def settled(request):
    preset, changes = SETS[request.param]
    p = get_preset(preset)
    params = p.params.replace(**changes)
    return params, simulate_impact(params, p.state0, (0.0, 300 * np.pi)).y[:, -1]


@pytest.mark.parametrize("q", [0.0, 2 / 21, 0.7])
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_the_resets_generated_derivatives_are_its_differences(q, side):
    c, out = 0.3, np.empty(4)

    def reset(wd):
        impact_reset_jet_kernel(0.0, np.array([0.0, 0.0, side, wd]), out, (c * abs(wd) ** q, q))
        return out.copy()

    wd, h = 1.3 * side, 1e-4
    jet = reset(wd)
    assert jet[0] == pytest.approx(-math.sqrt(1 - c * 1.3**q) * wd, rel=1e-14)
    for k in (1, 2, 3):
        difference = (reset(wd + h)[k - 1] - reset(wd - h)[k - 1]) / (2 * h)
        assert jet[k] == pytest.approx(difference, rel=1e-6, abs=1e-9), k


@pytest.mark.parametrize("variant", ["paper", "corrected"])
@pytest.mark.parametrize("phase, t1, sign", [(0.0, 2 * np.pi, 1.0), (2.0, np.pi, -1.0)])
def test_the_jets_first_and_second_derivatives_are_the_compiled_saltation_jacobian_and_its_differences(
    settled, phase, t1, sign, variant
):
    """Phi from the jets equals the compiled flow's product of propagators and saltation matrices,
    and D^2 P[u, v] the central difference of that Jacobian along v (1e-6 relative); on the full
    map and on the half-period map -phi_pi from another section; for (8) and for the corrected
    impact model (the wall's measured law: its flights from (8)'s orbit's state)."""
    params, x = settled
    flow = ImpactFlow(params, variant=variant)
    if phase:  # the orbit's state on that section
        x = flow.run(x, 0.0, phase, stick_speed=1e-9, max_impacts=100)[1][:, -1]
    _, phi, _, impacts, code = flow.strobe(x, phase, t1)
    assert code == 0 and len(impacts) >= 1
    D = ImpactMapDerivatives(params, x, t1, sign=sign, phase=phase, variant=variant)
    jets = np.column_stack([D.first(e) for e in np.eye(4)])
    np.testing.assert_allclose(jets, sign * phi, rtol=0, atol=1e-12 * np.abs(phi).max())
    u, v = np.random.default_rng(3).normal(size=(2, 4))
    h = 1e-6
    difference = (
        sign * (flow.strobe(x + h * v, phase, t1)[1] - flow.strobe(x - h * v, phase, t1)[1]) @ u / (2 * h)
    )
    second = D.second(u, v)
    assert np.abs(second - difference).max() < 1e-6 * np.abs(second).max()


@pytest.mark.parametrize("variant", ["paper", "corrected"])
def test_the_third_derivative_is_the_difference_of_the_second(settled, variant):
    params, x = settled
    u, v, w = np.random.default_rng(4).normal(size=(3, 4))
    h = 1e-5

    def second(y):
        return ImpactMapDerivatives(params, y, 2 * np.pi, variant=variant).second(u, v)

    third = ImpactMapDerivatives(params, x, 2 * np.pi, variant=variant).third(u, v, w)
    difference = (second(x + h * w) - second(x - h * w)) / (2 * h)
    assert np.abs(third - difference).max() < 1e-6 * np.abs(third).max()


def test_a_grazing_impact_is_refused_with_the_reason():
    params = get_preset("fig13").params
    with pytest.raises(ValueError, match="grazes the wall"):
        ImpactMapDerivatives(params, [0.0, 0.0, 1.0 - 1e-15, 5e-7], 2 * np.pi)
    level = ImpactFlow(params, variant="corrected").grazing_level  # the wall at its least speed
    with pytest.raises(ValueError, match="at the measured law's least speed 0.05"):
        ImpactMapDerivatives(params, [0.0, 0.0, level - 1e-12, 0.05], 2 * np.pi, variant="corrected")


def test_below_the_measured_laws_least_speed_the_derivatives_are_the_maps_own():
    """The corrected impact model's law is held constant below its least measured speed 0.05, so
    the map is smooth there: at a state whose one impact comes at 0.046, the jets' first and
    second derivatives are central differences of the map and of its compiled Jacobian."""
    params = get_preset("fig13").params
    flow = ImpactFlow(params, variant="corrected")
    y0, t1 = np.array([0.0, 0.0, 0.96, 0.1]), 2.0
    speeds = np.abs(flow.strobe(y0, 0.0, t1)[3][:, 2])
    assert len(speeds) == 1 and 0.04 < speeds[0] < 0.05
    derivatives = ImpactMapDerivatives(params, y0, t1, variant="corrected")
    u, v = np.random.default_rng(7).normal(size=(2, 4))
    h = 1e-6

    def end(y):
        return flow.strobe(y, 0.0, t1)[0]

    def jacobian(y):
        return ImpactMapDerivatives(params, y, t1, variant="corrected").jacobian()

    difference = (end(y0 + h * u) - end(y0 - h * u)) / (2 * h)
    assert np.abs(derivatives.first(u) - difference).max() < 1e-6 * np.abs(difference).max()
    assert np.abs(derivatives.jacobian() @ u - difference).max() < 1e-6 * np.abs(difference).max()
    second = (jacobian(y0 + h * v) - jacobian(y0 - h * v)) @ u / (2 * h)
    assert np.abs(derivatives.second(u, v) - second).max() < 1e-5 * np.abs(second).max()


@pytest.fixture(scope="module", params=["paper", "corrected"])
def fig13_impact_family(request):
    """The Fig. 13 set's orbits over sigma in [-2.5, 1]: the symmetric branch with its pitchforks
    and the asymmetric branches switched onto there; of (8) from its orbit at sigma = 1 (about
    2 s), of the corrected impact model from its asymmetric orbit at sigma = -2 (3 s)."""
    from slosh_bif.orbits.impact.branches import settled_orbit
    from slosh_bif.orbits.settings import BranchingSettings
    from slosh_bif.studies.chart.impact import impact_family

    variant = request.param
    p = get_preset("fig13")
    params = p.params if variant == "paper" else p.params.replace(sigma=-2.0)
    x0 = settled_orbit(params, p.state0, periods=200, variant=variant)
    family = impact_family(
        params,
        x0,
        param="sigma",
        p_range=(-2.5, 1.0),
        branching=BranchingSettings(doublings=False),
        variant=variant,
    )
    symmetric = next(nb for nb in family if nb.symmetric)
    pieces = [piece for nb in family if not nb.symmetric for piece in nb.branch.pieces]
    return params, symmetric, pieces, variant


def _on_section(params, x, p, phase, target, variant):
    """The state of the orbit of (8) through x on the section ``phase`` at the section ``target``."""
    flow = ImpactFlow(params.replace(sigma=p), variant=variant)
    later = (target - phase) % (2 * np.pi)
    return flow.run(x, phase, phase + later, stick_speed=1e-9, max_impacts=100)[1][:, -1] if later else x


def test_each_pitchforks_verdict_and_size_are_what_the_switched_asymmetric_branch_does(fig13_impact_family):
    """Soft (-2.008): the asymmetric pair is born where the symmetric orbit is unstable, stable;
    hard (0.437): where it is stable, unstable. Its two members (an orbit and its mirror image
    -phi_pi) differ in the critical component on the pitchfork's section by 2 growth |sigma - S|^0.5
    within 5 % where the unfolding parameter is at most 0.1 (the package's own switched branch,
    found without the coefficient, its piece through the pitchfork)."""
    from functools import partial

    from slosh_bif.orbits.criticality import describe, impact_criticality
    from slosh_bif.orbits.map_derivatives import crossing_rate

    params, symmetric, pair_pieces, variant = fig13_impact_family
    verdicts = impact_criticality(symmetric.branch, params, symmetric=True)
    seen = {}
    for piece, found in zip(symmetric.branch.pieces, verdicts):
        for k, v in found.items():
            sp = piece.branch.special[k]
            seen[round(sp.p, 2)] = v.verdict
            c = ("X", "X'", "w", "w'").index(v.component)
            # the growth is the section's (checked below), and the phrase says where it is read
            assert v.section == piece.phase and f"at the section tau = {piece.phase:.4g}" in describe(v)
            near = [
                (float(pp), bool(stable), _on_section(params, x, pp, other.phase, piece.phase, variant))
                for other in pair_pieces
                if np.abs(other.branch.p - sp.p).min() < 1e-6  # the piece through this pitchfork
                for pp, x, stable in zip(other.branch.p, other.branch.x, other.branch.stable)
                if 1e-7 < v.side * (pp - sp.p) < 0.02
            ]
            assert near, f"no asymmetric orbit on the predicted side of the BP at {sp.p}"
            parent_stable = [
                bool(s)
                for other in symmetric.branch.pieces
                for pp, s in zip(other.branch.p, other.branch.stable)
                if 1e-3 < v.side * (pp - sp.p) < 0.1
            ]
            assert (
                parent_stable
                and all(parent_stable) == (v.verdict == "hard")
                and all(stable == (v.verdict == "soft") for _, stable, _ in near)
            )
            rate = crossing_rate(
                lambda s: params.replace(sigma=s),
                sp.p,
                sp.x[:4],
                sp.tangent[:4] / sp.tangent[-1],
                "BP",
                v.nf,
                derivatives=partial(ImpactMapDerivatives, phase=piece.phase, variant=variant),
            )
            ratios = []
            for pp, _, y in near:
                if abs(pp - sp.p) * abs(rate) <= 0.1:
                    flow = ImpactFlow(params.replace(sigma=pp), variant=variant)
                    mirror = -flow.run(
                        y, piece.phase, piece.phase + np.pi, stick_speed=1e-9, max_impacts=100
                    )[1][:, -1]
                    ratios.append(abs(y[c] - mirror[c]) / 2 / (v.growth * np.sqrt(abs(pp - sp.p))))
            assert len(ratios) >= 2 and np.allclose(ratios, 1.0, atol=0.05), (sp.p, ratios)
    assert seen == ({-2.01: "soft", 0.44: "hard"} if variant == "paper" else {-2.03: "soft", 0.37: "hard"})
