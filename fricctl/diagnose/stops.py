"""End stops of a record, as the diagnosis reads them: :mod:`fricctl.identify.stops`,
re-exported (identification leaves the same contacts out: one detector for both)."""

from ..identify.stops import (LONE, MARGIN, MIN_IMPACTS, TOLERANCE, TORQUE_REACH, TRIM, EndStops,
                              end_stops)

__all__ = ["EndStops", "end_stops", "MARGIN", "TOLERANCE", "MIN_IMPACTS", "TORQUE_REACH", "TRIM",
           "LONE"]
