"""Recording: an integration as an xarray Dataset, and the response metrics read from one.

The record modes (:class:`FullRecord`, :class:`MetricsRecord`, :class:`SectionsRecord`,
:class:`WearRecord`)
say what :func:`mechanism.simulate` keeps of a run and build its Dataset; a new mode is a
new :class:`RecordMode` subclass (``docs/simulator.md``, *Record modes*).
"""

from ._metrics import (
    METRICS,
    ROD_STRAIN,
    friction_sign_flips,
    response_metrics,
    window_start,
)
from ._modes import (
    RECORD_MODES,
    FullRecord,
    MetricsRecord,
    RecordMode,
    RunTimes,
    SectionsRecord,
    WearRecord,
    available_variables,
    record_mode,
)
from ._record import LIGHT_VARIABLES, to_dataset

__all__ = [
    "LIGHT_VARIABLES",
    "METRICS",
    "RECORD_MODES",
    "ROD_STRAIN",
    "FullRecord",
    "MetricsRecord",
    "RecordMode",
    "RunTimes",
    "SectionsRecord",
    "WearRecord",
    "available_variables",
    "friction_sign_flips",
    "record_mode",
    "response_metrics",
    "to_dataset",
    "window_start",
]
