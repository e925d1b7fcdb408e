"""The unit of every column the package writes to CSV: a results table's (post-evaluation,
development, generations, findings) and a recording's series.

Every CSV that ``dart-reach`` writes (``export``, ``read --csv``) names its columns
``name [unit]`` where the column has a unit (``first_touch_s [s]``, ``hand_path [m]``,
``robot/joints/arm_hand/r_elbow [rad]``); labels, counts, flags, probabilities and ratios keep
the bare name (``unit`` returns ``""``). The meaning of each measure: docs/model/measures.md.
"""

from __future__ import annotations

import re

#: Table columns with a unit (a column ending in ``_s`` is in s, in ``_hz`` in Hz).
COLUMNS = {
    **{c: "m" for c in ("ball_x", "ball_y", "ball_z", "hand_path", "hand_amplitude",
                        "hand_shoulder_mean", "elbow_freezing", "hand_ball_initial",
                        "hand_ball_min")},
    **{c: "m/s" for c in ("speed", "speed_peak", "speed_final")},
    **{f"var_{g}{w}": "rad" for g in ("elbow", "shoulder", "trunk") for w in ("", "_before")},
}
#: Recording series by entity prefix (``recording.rrd``'s entities).
SERIES = (("robot/positions/", "m"), ("robot/joints/", "rad"),
          ("variability/joints/", "rad"), ("variability/distance/", "m"))


def unit(column: str) -> str:
    """The unit of a column or series name ('' for none: a label, count, flag or ratio)."""
    if column in COLUMNS:
        return COLUMNS[column]
    if column == "sim_time" or re.search(r"_s$", column):
        return "s"
    if column.endswith("_hz"):
        return "Hz"
    for prefix, u in SERIES:
        if column.startswith(prefix):
            return u
    return ""


def with_unit(column: str) -> str:
    """The column's CSV header: ``name [unit]``, or the bare name without a unit."""
    u = unit(column)
    return f"{column} [{u}]" if u else column
