"""What a located sign change of a multiplier test is: a crossing of the unit circle, or a jump of
an impact map's Jacobian (a non-smooth point), which is none."""

import numpy as np

from slosh_bif.orbits.multipliers import describe_crossing


def test_a_period_doubling_has_a_multiplier_at_minus_one_and_a_jump_is_none():
    pair = [0.652 + 0.4736j, 0.652 - 0.4736j]
    crossing = np.array([-1.0 + 1e-9, *pair, 0.1])
    assert describe_crossing("PD", crossing, symmetric=False).startswith("period doubling")
    assert describe_crossing("BP", crossing, symmetric=True).startswith("symmetry-breaking pitchfork")
    # the corrected impact model's map across its law's clamp: its largest multiplier jumps from
    # +77 to -77, and PD's test (the product of 1 + mu) changes sign with no multiplier near -1
    jumped = np.array([-77.5494, *pair, -8e-4])
    assert describe_crossing("PD", jumped, symmetric=False) is None
    assert describe_crossing("BP", jumped, symmetric=True) is None
    # a double -1 (a free particle's drift) is no simple crossing either
    assert describe_crossing("PD", np.array([-1.0, -1.0 + 1e-7, 0.5, 0.2]), symmetric=False) is None
