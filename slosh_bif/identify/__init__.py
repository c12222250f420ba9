"""From measurements to the model: the wall's parameters identified from measured data, with
their uncertainty and what the data cannot tell. Impact records (incoming and outgoing particle
speeds) fitted by the restitution law (21): :mod:`.impact_records`; their outputs:
:mod:`.output`."""

from slosh_bif.identify.impact_records import (
    FREE_NAMES,
    ImpactRecords,
    WallFit,
    fit_wall,
    read_impact_records,
)

__all__ = ["ImpactRecords", "WallFit", "read_impact_records", "fit_wall", "FREE_NAMES"]
