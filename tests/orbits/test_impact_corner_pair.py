"""The corrected impact model's corner met by two impacts at once: a branch of a random set
(seed 305 of the robustness draws) stalls where a mirror pair of slow impacts reaches the measured
law's least speed together. The orbit beyond, found from the run's last points, takes one of the
pair across and holds the other, and returns to itself under the flow at another sample step."""

from types import SimpleNamespace

import numpy as np
import pytest

from slosh_bif import get_preset, simulate_impact
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.orbits.impact.law_corner import across_the_corner, corner_sides
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")

# the run's last points (sigma, state on the section tau = PHASE), the slower of the pair falling
# to v_min = 0.05 with sigma; the last is the stalled END
RUN = [
    (-0.5251563570820801, [-1.6031229435695493, 3.618795591930465, 0.46458308997853404, 0.19632091207931918]),
    (-0.5251593076893788, [-1.6031098936143207, 3.618790952247515, 0.4645836689033572, 0.1963213607892584]),
    (-0.5251604879367475, [-1.6031046736409538, 3.6187890963518328, 0.4645839004720587, 0.1963215402666246]),
    (-0.5251614321365495, [-1.603100497666332, 3.6187876116246414, 0.46458408572646914, 0.1963216838450211]),
    (
        -0.5251614557415135,
        [-1.6031003932664118, 3.6187875745080986, 0.46458409035787973, 0.19632168743541678],
    ),
    (-0.5251614651835559, [-1.6031003515070656, 3.618787559659662, 0.46458409221038266, 0.19632168887056045]),
    (-0.5251614661277719, [-1.603100347331232, 3.618787558174525, 0.4645840923956209, 0.196321689013914]),
]
PHASE = 5.144708599910398


def test_one_of_a_pair_of_impacts_at_the_corner_is_taken_across_and_the_orbit_closes():
    at = get_preset("fig10").params.replace(
        eps=0.0723, beta=0.223, gamma=0.297, sigma=-0.4822, Abar=2.583, lam=0.563, chi=1.082, n=6, pbar=2
    )
    problem = ImpactOrbitProblem(at, phase=PHASE, impacts=4, variant="corrected")
    p_end, x_end = RUN[-1]
    speeds = np.abs(problem.evaluate(np.array(x_end), p_end).impacts[:, 2])
    assert np.sum(np.abs(speeds - 0.05) < 1e-6) == 2  # the pair, both at the corner
    branch = SimpleNamespace(p=np.array([p for p, _ in RUN]), x=np.array([x for _, x in RUN]))
    end = SimpleNamespace(index=len(RUN) - 1, x=np.array(x_end), p=p_end)
    found = across_the_corner(problem, branch, end, (-6.0, 8.0))
    assert found is not None
    x, q, _ = found
    assert abs(q - p_end) < 1e-4 and sum(corner_sides(problem, x, q)) == 1  # one across, one held
    run = simulate_impact(
        at.replace(sigma=float(q)),
        x,
        (PHASE, PHASE + 2 * np.pi),
        sample_step=0.02,
        variant="corrected",
        continued=True,
    )
    assert run.success
    np.testing.assert_allclose(run.y[:, -1], x, rtol=0, atol=1e-7)
