"""From measurements to the model: the wall's (and the vessel's) parameters identified from
measured data, with their uncertainty and what the data cannot tell.

* A frequency response, points (sigma, A), or (f_hz, A_m) through a tank file, fitted by the
  slow flow's steady states (46) and the impact-free response, or by the orbits of (9) or (8):
  :mod:`.response_data`, :mod:`.response_model`, :mod:`.response_orbits`, :mod:`.response_impact`,
  :mod:`.response_fit` (its statistics :mod:`.response_stats`, integers
  :mod:`.response_integers`, result :mod:`.response_result`), and their outputs
  :mod:`.response_output`;
* a free decay or a forced record in time, fitted by the slow flow (45):
  :mod:`.time_series` and its outputs :mod:`.time_series_output`;
* a settled forced record, fitted sample by sample by the orbit of (9) or (8) it follows:
  :mod:`.steady_record`, :mod:`.steady_fit` and its outputs :mod:`.steady_output`;
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
from slosh_bif.identify.response_fit import RESPONSE_FREE, fit_response
from slosh_bif.identify.response_result import ResponseFit

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
