"""Parameters: validation messages name the parameter, range and value; presets convert (u, v)."""

import dataclasses
import math

import numpy as np
import pytest

from slosh_bif import PRESETS, Params, get_preset
from slosh_bif.model.presets import state_from_uv, uv_from_state

BASE = dict(eps=0.05, beta=0.0, gamma=0.2, sigma=1.0, Abar=3.0, lam=0.35, chi=0.2, n=50, pbar=0)


def make(**changes):
    return Params(**{**BASE, **changes})


@pytest.mark.parametrize(
    "changes, pattern",
    [
        (dict(eps=0.0), r"parameter eps must be in \(0, inf\); got 0\.0"),
        (dict(eps=-0.1), r"parameter eps must be in \(0, inf\); got -0\.1"),
        (dict(gamma=-1.0), r"parameter gamma must be in \[0, inf\); got -1\.0"),
        (dict(lam=-0.01), r"parameter lam must be in \[0, inf\); got -0\.01"),
        (dict(chi=-0.2), r"parameter chi must be in \(0, inf\); got -0\.2"),
        (dict(n=0), r"parameter n must be in integers >= 1; got 0"),
        (dict(n=2.5), r"parameter n must be in integers >= 1; got 2\.5"),
        (dict(n="50"), r"parameter n must be in integers >= 1; got '50'"),
        (
            dict(pbar=1),
            r"parameter pbar must be in integers with p = \(pbar \+ n\)/2 a non-negative integer.*got 1",
        ),
        (dict(pbar=0.5), r"parameter pbar must be in integers > -\(n\+1\) = -51; got 0\.5"),
        (
            dict(n=6, pbar=-7),
            r"parameter pbar must be in integers > -\(n\+1\) = -7 \(eq\. 19 diverges otherwise\); got -7",
        ),
        (dict(n=6, pbar=-9), r"parameter pbar must be in integers > -\(n\+1\) = -7.*got -9"),
        (
            dict(lam=5.0),
            r"restitution coefficient kappa .* must be real in \(0, 1\]; with lam=5\.0, chi=0\.2, "
            r"n=50, pbar=0",
        ),
        (
            dict(n=6, pbar=2),
            r"restitution coefficient kappa .* must be real in \(0, 1\]; with lam=0\.35, chi=0\.2, "
            r"n=6, pbar=2",
        ),
        (dict(sigma=math.nan), r"parameter sigma must be in \(-inf, inf\); got nan"),
        (dict(Abar=math.inf), r"parameter Abar must be in \[0, inf\); got inf"),
        (dict(beta=-math.inf), r"parameter beta must be in \[0, inf\); got -inf"),
        (dict(n=math.inf), r"parameter n must be in integers >= 1; got inf"),
    ],
)
def test_validation_names_parameter_range_and_value(changes, pattern):
    with pytest.raises(ValueError, match=pattern):
        make(**changes)


def test_params_are_immutable_and_replace_validates():
    params = make()
    with pytest.raises(dataclasses.FrozenInstanceError):
        params.eps = 0.1
    assert params.replace(sigma=2.0).sigma == 2.0
    with pytest.raises(ValueError, match="parameter eps"):
        params.replace(eps=0)
    with pytest.raises(ValueError, match=r"unknown parameter\(s\) \['zeta'\]"):
        params.replace(zeta=1)


def test_integral_floats_become_ints_and_p_follows():
    params = make(n=6.0, pbar=-2.0)
    assert params.n == 6 and isinstance(params.n, int)
    assert params.p == 2 and 2 * params.p - params.n == params.pbar


def test_elastic_wall_is_allowed():
    assert make(lam=0.0).lam == 0.0


def test_overrides_parse_and_reject():
    params = make().with_overrides(["Abar=2", " sigma = -1.5"])
    assert (params.Abar, params.sigma) == (2.0, -1.5)
    with pytest.raises(ValueError, match="--set takes name=value"):
        make().with_overrides(["Abar"])
    with pytest.raises(ValueError, match="--set takes name=value with name one of"):
        make().with_overrides(["A=1"])
    with pytest.raises(ValueError, match="parameter gamma needs a number; got 'fast'"):
        make().with_overrides(["gamma=fast"])


def test_all_figure_presets_exist_and_validate():
    assert set(PRESETS) == {"fig9a", "fig9b", "fig10", "fig11a", "fig11b", "fig12", "fig13", "fig14", "fig15"}
    for preset in PRESETS.values():
        assert isinstance(preset.params, Params)
    with pytest.raises(ValueError, match="unknown preset 'fig99'"):
        get_preset("fig99")


def test_preset_state_is_the_coordinate_change_of_the_paper():
    preset = get_preset("fig10")  # u0 = 0, u0' = 3, v0 = -0.97, v0' = 0
    eps = preset.params.eps
    np.testing.assert_allclose(preset.state0, [0 + eps * -0.97, 3.0, 0 + 0.97, 3.0], rtol=0, atol=1e-15)
    rng = np.random.default_rng(0)
    uv = rng.normal(size=(10, 4))
    np.testing.assert_allclose(uv_from_state(state_from_uv(*uv.T, eps=eps).T, eps), uv, atol=1e-14)


def test_a_huge_dissipation_exponent_is_a_range_error_not_an_overflow():
    # ((n + 1) / chi) ** (pbar / (n + 1)) overflows a float at pbar = 1e9: no real restitution coefficient
    with pytest.raises(ValueError, match="restitution coefficient kappa"):
        get_preset("fig10").params.replace(pbar=1_000_000_000)
