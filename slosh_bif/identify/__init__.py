"""From measurements to the model: the wall's (and the vessel's) parameters identified from
measured data, with their uncertainty and what the data cannot tell.

* A frequency response, points (sigma, A) of the impacting regime, fitted by the slow flow's
  steady states (46): :mod:`.response_data`, :mod:`.response_model`, :mod:`.response_fit`, and
  their outputs :mod:`.response_output`;
* impact records (incoming and outgoing particle speeds) fitted by the restitution law (21):
  :mod:`.impact_records`, and their outputs :mod:`.output`.
"""

from slosh_bif.identify.impact_records import (
    FREE_NAMES,
    ImpactRecords,
    WallFit,
    fit_wall,
    read_impact_records,
)
from slosh_bif.identify.response_data import ResponseData, read_response_data
from slosh_bif.identify.response_fit import RESPONSE_FREE, ResponseFit, fit_response

__all__ = [
    "ImpactRecords",
    "WallFit",
    "read_impact_records",
    "fit_wall",
    "FREE_NAMES",
    "ResponseData",
    "read_response_data",
    "ResponseFit",
    "fit_response",
    "RESPONSE_FREE",
]
