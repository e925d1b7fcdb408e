"""What a trial recording holds and how it is shown: the entity layout (``SIGNALS``), the
measures of its property ``trial`` (``MEASURES``), what it is about (``TrialInfo``) and its
default layout in the viewer (``trial_blueprint``, ``PANELS``). ``rrd`` writes and reads it.

Entity layout of a trial recording::

    world/robot            the robot's visual boxes (static sizes, poses per step; touching
                           segments drawn yellow)
    world/pendulum         the ball's string: pivot (static) and string per step
    world/spheres          the head, the ball (red) and the palm point (blue), per step
    world/paths            the whole paths of the hand and of the ball
    robot/joints/{head_torso,arm_hand}    joint angles per motor (rad)
    robot/contacts                        1 = the segment touches the ball (icub.HAND_SEGMENTS)
    robot/positions                       {hand,shoulder,ball}/{x,y,z} (m, the iCub root frame)
    sensors/proprio/{head_torso,arm_hand} the network's inputs: proprioception, and
    sensors/{touch,sight,offset}          touch, sight, offset (25 in all)
    network/hidden                        internal neuron states h0..h7 (the motor
                                          neurons' are the targets': 2 m - 1)
    motor/targets/{head_torso,arm_hand}   the targets sent to the joints, in [-1, 1]
    fitness                               p_sight, p_touch, p_multimodal (Eq. 5)
    variability/joints                    movement variability per step (Fig. 6), window/
                                          and cumulative/{elbow,shoulder,trunk}: s.d. of the
                                          joints over the last 2 s and since the start (rad;
                                          the last step's cumulative is the trial's var_*)
    variability/distance                  hand_shoulder, hand_ball (m)

Each of these is one ``Scalars`` entity (one panel of the default layout, ``PANELS``) with its
series names logged once as static ``SeriesLines``; ``read_rrd`` turns them back into one
polars column per series (``"sensors/proprio/arm_hand/r_elbow"``), one row per step. The
recording's property ``trial`` says condition, phase, replication, individual, sector, trial
seed and sensory condition, and holds the trial's measures (``MEASURES`` of
``metrics.trial_metrics``, as in evaluation.parquet).
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from ..measures import metrics
from ..model.ctrnn import MOTOR_NAMES, N_HIDDEN, OFFSET, PROPRIO, SIGHT, TOUCH, TOUCH_NAMES
from ..model.icub import HAND_SEGMENTS
from ..model.task import TrialData

#: Version of the entity layout, in every recording's properties (2: the five signal entities;
#: 3: one entity per panel, movement variability, the trial's measures, the pendulum).
LAYOUT = 3
XYZ = ("x", "y", "z")
JOINT_GROUP_NAMES = tuple(metrics.JOINT_GROUPS)

#: The time series of a trial: (entity, series names, the (T, n) array of a record). Each
#: entity is what one panel of the default layout shows (a few lines; every entity's column
#: carries its own copy of the timelines, a cost in size and time per trial). A series is read back
#: as the column "<entity>/<name>".
_HT, _AH = slice(0, 6), slice(6, 14)  # motors of head and torso; of arm and hand
SIGNALS = (
    ("robot/joints/head_torso", MOTOR_NAMES[_HT], lambda d: d.joints[:, _HT]),
    ("robot/joints/arm_hand", MOTOR_NAMES[_AH], lambda d: d.joints[:, _AH]),
    ("robot/contacts", HAND_SEGMENTS, lambda d: d.contacts),
    ("robot/positions", tuple(f"{b}/{a}" for b in ("hand", "shoulder", "ball") for a in XYZ),
     lambda d: np.concatenate([d.hand, d.shoulder, d.ball], axis=1)),
    ("sensors/proprio/head_torso", MOTOR_NAMES[_HT], lambda d: d.sensors[:, PROPRIO][:, _HT]),
    ("sensors/proprio/arm_hand", MOTOR_NAMES[_AH], lambda d: d.sensors[:, PROPRIO][:, _AH]),
    ("sensors/touch", TOUCH_NAMES, lambda d: d.sensors[:, TOUCH]),
    ("sensors/sight", ("x", "y", "distance"), lambda d: d.sensors[:, SIGHT]),
    ("sensors/offset", ("x", "y"), lambda d: d.sensors[:, OFFSET]),
    # the motor neurons' states are the targets' (2 m - 1, ctrnn.motor_targets): not repeated
    ("network/hidden", tuple(f"h{i}" for i in range(N_HIDDEN)), lambda d: d.hidden),
    ("motor/targets/head_torso", MOTOR_NAMES[_HT], lambda d: d.targets[:, _HT]),
    ("motor/targets/arm_hand", MOTOR_NAMES[_AH], lambda d: d.targets[:, _AH]),
    ("fitness", ("p_sight", "p_touch", "p_multimodal"),
     lambda d: np.stack([d.p_sight, d.p_touch, d.p_multimodal], axis=1)),
    ("variability/joints", tuple(f"{kind}/{g}" for kind in ("window", "cumulative")
                                 for g in JOINT_GROUP_NAMES), lambda d: _joint_variability(d)),
    ("variability/distance", ("hand_shoulder", "hand_ball"),
     lambda d: np.stack([metrics.hand_shoulder_distance(d.hand, d.shoulder),
                         metrics.hand_ball_distance(d.hand, d.ball)], axis=1)),
)

#: The per-trial measures a recording carries in its property ``trial``.
MEASURES = ("fitness", "reached", "reached_inner", "grasped", "first_touch_s",
            "first_touch_inner_s", "first_grasp_s", "speed", "speed_peak", "speed_final",
            "straightness", "straightness_onset", "movement_units", "var_elbow", "var_shoulder",
            "var_trunk", "hand_shoulder_mean", "hand_shoulder_cv", "elbow_freezing",
            "hand_ball_initial", "hand_ball_min", "approach", "heading", "hand_path",
            "hand_amplitude", "babbling_freq_hz", "babbling_share", "babbling",
            "anticipatory_grasp", "grasp_lead_s", "palm_up_swipe", "diverged")


def _joint_variability(data: TrialData) -> np.ndarray:
    """(T, 6): window and cumulative movement variability per joint group
    (``metrics.variability_over_time``)."""
    v = metrics.variability_over_time(data.joints)
    return np.stack([v[f"{kind}/{g}"] for kind in ("window", "cumulative")
                     for g in JOINT_GROUP_NAMES], axis=1)


@dataclass(frozen=True)
class TrialInfo:
    """What a trial recording is about (its recording properties)."""

    condition: str
    phase: str
    replication: int
    individual: int  # rank in the final population (post-evaluation) or index (training)
    sector: int
    trial: int  # index of the trial in its series (0..44 in the post-evaluation)
    trial_seed: str  # the seed of the trial's random positions, or "systematic"
    senses: str = "normal"
    generation: int = -1  # training recordings: the generation; -1 otherwise

    def name(self) -> str:
        return (f"{self.condition}/{self.phase} rep {self.replication} #{self.individual} "
                f"{self.senses} trial {self.trial} (sector {self.sector})")


#: Qualitative colours of the lines of one panel (matplotlib's tab10): a panel never shows
#: more than ten lines, and its lines never share a colour.
PALETTE = ((31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
            (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207))

#: The time-series panels of a trial: (panel name, the entities of ``SIGNALS`` it shows).
PANELS = (
    ("proprioception: head, torso", ["sensors/proprio/head_torso"]),
    ("proprioception: arm, hand", ["sensors/proprio/arm_hand"]),
    ("touch", ["sensors/touch"]),
    ("sight and hand-ball offset", ["sensors/sight", "sensors/offset"]),
    ("internal neurons", ["network/hidden"]),
    ("motor targets: head, torso", ["motor/targets/head_torso"]),
    ("motor targets: arm, hand", ["motor/targets/arm_hand"]),
    ("fitness (Eq. 5)", ["fitness"]),
    ("joint angles: head, torso (rad)", ["robot/joints/head_torso"]),
    ("joint angles: arm, hand (rad)", ["robot/joints/arm_hand"]),
    ("hand contacts with the ball", ["robot/contacts"]),
    ("movement variability (rad): s.d. over the last 2 s, and since the start",
     ["variability/joints"]),
    ("hand-shoulder and hand-ball distance (m)", ["variability/distance"]),
)
#: The 3D view's camera: in front of the robot, to its right and above, on the sector area.
CAMERA = {"position": (-0.85, 0.55, 0.45), "look_target": (-0.18, 0.1, 0.12),
          "eye_up": (0.0, 0.0, 1.0)}


def _colours(entities) -> dict[str, list]:
    """Distinct colours for the lines of one panel, in order across its entities."""
    names = dict((e, n) for e, n, _ in SIGNALS)
    out, k = {}, 0
    for e in entities:
        out[e] = [PALETTE[(k + i) % len(PALETTE)] for i in range(len(names[e]))]
        k += len(names[e])
    return out


def _panel(name: str, entities: list[str]) -> rrb.TimeSeriesView:
    """A panel of a few entities' lines in distinct colours; with several entities each line's
    legend name is prefixed with its entity's last part ("offset x")."""
    origin = os.path.commonpath(entities)
    names = dict((e, n) for e, n, _ in SIGNALS)
    overrides = {}
    for e, colours in _colours(entities).items():
        label = [f"{e.rpartition('/')[2]} {n}" for n in names[e]] if len(entities) > 1 else None
        overrides[e] = rr.SeriesLines.from_fields(colors=colours, names=label)
    return rrb.TimeSeriesView(name=name, origin=f"/{origin}",
                              contents=[f"+ /{e}" for e in entities],
                              plot_legend=rrb.Corner2D.LeftTop, overrides=overrides)


@functools.cache
def trial_blueprint() -> rrb.Blueprint:
    """The default layout of a trial (built once per process): the robot and the ball in 3D
    from a fixed camera (Z up; the pendulum's string drawn; touching hand segments yellow),
    the same scene with the hand and ball paths, and tabs of small time-series panels of a
    few distinct lines each (``PANELS``). Playback runs at real time on ``sim_time``."""
    scene = rrb.Spatial3DView(
        name="robot and ball", origin="world", contents=["+ $origin/**", "- /world/paths/**"],
        eye_controls=rrb.EyeControls3D(**CAMERA), line_grid=rrb.LineGrid3D(visible=False))
    paths = rrb.Spatial3DView(name="hand and ball paths", origin="world",
                              eye_controls=rrb.EyeControls3D(**CAMERA),
                              line_grid=rrb.LineGrid3D(visible=False))
    panels = [_panel(*p) for p in PANELS]
    tabs = rrb.Tabs(
        rrb.Grid(*panels[:4], name="sensors", grid_columns=2),
        rrb.Grid(*panels[4:8], name="network, motors, fitness", grid_columns=2),
        rrb.Grid(*panels[8:11], name="robot", grid_columns=1),
        rrb.Grid(*panels[11:], name="movement variability", grid_columns=1))
    return rrb.Blueprint(
        rrb.Horizontal(rrb.Vertical(scene, paths, row_shares=[3, 2]), tabs,
                       column_shares=[1, 1]),
        rrb.TimePanel(timeline="sim_time", playback_speed=1.0),
        collapse_panels=False,
    )
