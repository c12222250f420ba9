"""The stiff-wall limit: (9)'s orbit (shooting on its DOP853 flow) approaches the corrected impact
model's (Newton on its exact flow) as n grows, and (8)'s first-order coefficients keep it away."""

import pytest

from slosh_bif import get_preset
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.studies.stiff_wall import (
    convergence_rate,
    markdown_table,
    simplifications,
    simplifications_table,
    stiff_wall_points,
)

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the corrected impact model runs on the compiled flow")


def test_the_orbits_of_9_converge_to_the_corrected_impact_model_as_the_wall_stiffens():
    points = stiff_wall_points(get_preset("fig10").params, [3.0], [50, 200])
    assert all(p.status == "ok" and p.impacts == 2 for p in points)
    coarse, fine = points
    assert fine.corrected_error < coarse.corrected_error / 10 and fine.corrected_error < 1e-4
    # (8) with its first-order coefficients stays a few percent off at any n (eps sigma = 0.15)
    assert fine.paper_error > 1e-2
    assert convergence_rate(points, 3.0) < -1.5
    assert "n^" in markdown_table(points)


def test_the_corrected_model_is_9_up_to_the_contact_and_8s_two_simplifications_each_move_it():
    (row,) = simplifications(get_preset("fig10").params, [3.0])
    # the simulated orbits agree with the shooting above: corrected 4e-4 from (9) at n = 50
    assert abs(row.corrected - row.smooth) < 1e-3 * row.smooth
    for value in (row.paper, row.exact_flights, row.measured_wall):  # each a few percent off
        assert abs(value - row.smooth) > 5e-3 * row.smooth
    assert "+" in simplifications_table([row]) or "-" in simplifications_table([row])


def test_bad_input_is_refused_before_any_work():
    params = get_preset("fig10").params
    with pytest.raises(ValueError, match="sigma"):
        stiff_wall_points(params, [], [50])
    with pytest.raises(ValueError, match="pbar"):
        stiff_wall_points(params.replace(pbar=2), [3.0], [51])
