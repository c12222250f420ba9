"""The integer power of the generated kernels: repeated squaring (compiled) against libm's pow."""

import math

import numpy as np
import pytest

from slosh_bif.model.powers import int_power, int_power_by_squaring


@pytest.mark.parametrize("k", [0, 1, 2, 12, 13, 20, 101, 201])
def test_squaring_agrees_with_pow_to_a_few_roundings(k):
    rng = np.random.default_rng(k)
    for x in np.concatenate([rng.uniform(-1.3, 1.3, 200), [0.0, -0.0, 1.0, -1.0]]):
        exact = math.pow(x, k)
        got = int_power_by_squaring(float(x), float(k))
        # a squaring doubles the relative error it is given: k roundings at most (2.2e-14 at k = 101)
        assert abs(got - exact) <= (k + 1) * 2.3e-16 * abs(exact), (x, k)
        assert math.copysign(1.0, got) == math.copysign(1.0, exact) or exact == 0.0


def test_an_exponent_that_is_not_whole_falls_back_to_pow():
    assert int_power_by_squaring(1.7, 2.5) == 1.7**2.5
    assert int_power_by_squaring(1.7, -2.0) == 1.7**-2.0


def test_the_compiled_kernels_use_squaring_and_python_uses_pow():
    import numba

    from slosh_bif.flows.smooth import dop853  # noqa: F401  registers the compiled implementation

    compiled = numba.njit(lambda x, k: int_power(x, k))
    for x, k in ((1.01, 101.0), (-0.97, 13.0), (0.5, 0.0)):
        assert compiled(x, k) == int_power_by_squaring(x, k)
        assert int_power(x, k) == x**k
