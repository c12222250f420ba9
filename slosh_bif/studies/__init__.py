"""Questions that combine the wings: the slow flow against the orbits (compare, trust maps),
work-precision benchmarks, the answer ladder (the lightest adequate model), the paper's figures."""

from slosh_bif.studies.compare import compare_rows, compare_table
from slosh_bif.studies.ladder import Answer, answer, model_choice
from slosh_bif.studies.trust import TrustPoint, trust_map, trust_point

__all__ = [
    "answer",
    "Answer",
    "model_choice",
    "compare_rows",
    "compare_table",
    "trust_point",
    "trust_map",
    "TrustPoint",
]
