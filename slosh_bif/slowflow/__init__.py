"""The slow flow of the multiple-scales analysis: (43), (45) on S+, the steady states and the
frequency response of (46), the critical forcing Abar_b, and their CSV/PNG output."""

from slosh_bif.slowflow.critical import (
    CriticalCurve,
    CriticalPoint,
    critical_curve,
    critical_forcing,
)
from slosh_bif.slowflow.flow import (
    AsymptoticsWarning,
    SlowFlow,
    SlowTrajectory,
    asymptotics_concerns,
)
from slosh_bif.slowflow.steady_states import (
    FrequencyResponse,
    SteadyStateProblem,
    forcing_response,
    frequency_response,
)

__all__ = [
    "SlowFlow",
    "SlowTrajectory",
    "AsymptoticsWarning",
    "asymptotics_concerns",
    "SteadyStateProblem",
    "FrequencyResponse",
    "frequency_response",
    "forcing_response",
    "CriticalPoint",
    "CriticalCurve",
    "critical_forcing",
    "critical_curve",
]
