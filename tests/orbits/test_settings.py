"""The settings objects: each field checked on construction, the error naming the object's field."""

import pytest

from slosh_bif import get_preset
from slosh_bif.orbits import (
    BranchingSettings,
    ShootingSettings,
    StartSettings,
    scan_families,
    trace_orbits,
)
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.studies.chart import ChartSettings


@pytest.mark.parametrize(
    "make, message",
    [
        (
            lambda: ShootingSettings(segments=0),
            r"ShootingSettings\.segments must be an integer in \[1, 64\]; got 0",
        ),
        (lambda: ShootingSettings(segments=4.0), r"ShootingSettings\.segments must be an integer"),
        (lambda: ShootingSettings(rtol=1e-2), r"ShootingSettings\.rtol must be in \[1e-14, 1e-4\]"),
        (lambda: ShootingSettings(atol=0.0), r"ShootingSettings\.atol must be in \(0, 1e-4\]"),
        (
            lambda: ShootingSettings(backend="cuda"),
            r"ShootingSettings\.backend must be one of auto, numba, scipy; got 'cuda'",
        ),
        (
            lambda: ShootingSettings(points_per_2pi=4),
            r"ShootingSettings\.points_per_2pi must be an integer in \[8, 65536\]",
        ),
        (
            lambda: BranchingSettings(max_branches=0),
            r"BranchingSettings\.max_branches must be an integer >= 1",
        ),
        (lambda: BranchingSettings(switch="no"), r"BranchingSettings\.switch must be True or False"),
        (lambda: StartSettings(points=0), r"StartSettings\.points must be an integer >= 1"),
        (lambda: StartSettings(seed=-1), r"StartSettings\.seed must be an integer >= 0"),
        (lambda: ChartSettings(seeds=-1), r"ChartSettings\.seeds must be an integer >= 0"),
        (lambda: ChartSettings(workers=0), r"workers must be an integer >= 1"),
    ],
)
def test_a_bad_setting_is_refused_on_construction_naming_its_field(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_settings_are_frozen_and_replaced_whole():
    shooting = ShootingSettings()
    with pytest.raises(AttributeError):
        shooting.segments = 8
    assert shooting.replace(segments=8).segments == 8 and shooting.segments == 4


def test_the_old_keyword_arguments_are_refused_by_name():
    P = get_preset("fig10").params
    with pytest.raises(TypeError, match="switch"):
        trace_orbits(P, [0.0, 0.0, 0.0, 0.0], switch=False, interval=ParameterRange(lo=-1.0, hi=1.0))
    with pytest.raises(TypeError, match="seed"):
        scan_families(P, [0.0, 0.0, 0.0, 0.0], seed=3, interval=ParameterRange(lo=-1.0, hi=1.0))
