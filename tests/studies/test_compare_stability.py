"""A stable slow-flow state's verdict (is there a stable 2pi-orbit there?) must not depend on where
the continuation put its points or on the last bits of libm: glibc picks cos and pow by the CPU,
and on this machine the FMA and non-FMA code paths gave 4 of 48 different rows of the Fig. 13 trust
map before the special points decided (issue 18)."""

import os
import subprocess
import sys
import types

import numpy as np
import pytest

from slosh_bif.continuation.branch import SpecialPoint
from slosh_bif.studies.compare import stable_at


def _branch(p, stable, special):
    return types.SimpleNamespace(
        p=np.array(p, float),
        stable=np.array(stable),
        special=tuple(SpecialPoint(k, i, q, np.zeros(1), (q, q)) for k, i, q in special),
    )


@pytest.mark.parametrize("flag_at_the_point", [True, False])
def test_a_special_point_on_the_branch_does_not_decide_by_its_own_flag(flag_at_the_point):
    # The NS point itself is a branch point at p = 2; its multiplier is 1 to rounding.
    b = _branch([0, 1, 2, 3], [True, True, flag_at_the_point, False], [("NS", 2, 2.0)])
    assert stable_at(b, slice(1, 3), 1.5) is True
    assert stable_at(b, slice(2, 4), 2.5) is False


def test_a_special_point_inside_a_segment_splits_it():
    b = _branch([0, 1, 2, 3], [True, True, False, False], [("LP", 1, 1.4)])
    assert stable_at(b, slice(1, 3), 1.3) is True and stable_at(b, slice(1, 3), 1.6) is False
    # the same with the parameter decreasing along the branch
    r = _branch([3, 2, 1, 0], [False, False, True, True], [("LP", 1, 1.4)])
    assert stable_at(r, slice(1, 3), 1.3) is True and stable_at(r, slice(1, 3), 1.6) is False
    # without a located special point, ends that disagree give "unstable"
    assert stable_at(_branch([0, 1], [True, False], []), slice(0, 2), 0.5) is False


def test_a_special_point_of_another_part_of_the_branch_does_not_count():
    # The Fig. 10 family's asymmetric branch: a segment from a stable orbit to a located PD point
    # (its own flag unstable to rounding), and, further on, after the branch turned, a fold at a
    # parameter value inside that segment's range. The PD alone decides the segment.
    b = _branch(
        [0, 1, 2, 3, 1.4, 0.5],
        [True, True, False, False, False, True],
        [("PD", 2, 2.0), ("LP", 4, 1.4)],
    )
    assert stable_at(b, slice(1, 3), 1.2) is True
    assert stable_at(b, slice(4, 6), 1.0) is True


_POINT = (
    "from slosh_bif import NO_SWITCHING, get_preset; from slosh_bif.studies.trust import trust_point; "
    "t = trust_point(get_preset('fig13').params.replace(eps=0.02, beta=0.0, n=50), "
    "branching=NO_SWITCHING); print(repr((t.agree, t.confirmed)))"
)


@pytest.mark.slow  # three trust maps (18 s)
@pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="GLIBC_TUNABLES selects glibc's libm code path"
)
def test_the_trust_verdicts_are_the_same_on_glibcs_fma_and_plain_code_paths():
    # On a CPU with FMA and AVX2 the second run takes libm's other cos and pow (last bits differ);
    # where the CPU has neither, both runs take the same path and the test says nothing.
    env = dict(os.environ, GLIBC_TUNABLES="glibc.cpu.hwcaps=-AVX2_Usable,-FMA_Usable,-AVX2,-FMA")
    runs = [
        subprocess.run([sys.executable, "-c", _POINT], capture_output=True, text=True, env=e, timeout=300)
        for e in (dict(os.environ), env)
    ]
    assert all(r.returncode == 0 for r in runs), [r.stderr[-2000:] for r in runs]
    assert runs[0].stdout == runs[1].stdout
