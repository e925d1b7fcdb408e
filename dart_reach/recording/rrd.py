"""Rerun recordings of trials and of training, and reading them back (the only module that
imports rerun).

A trial is recorded after it has run, from its ``TrialData``: every signal is sent as one column
per entity with ``send_columns`` (one ``log`` call costs ~50 µs, so logging step by step would cost
more than the physics; see ``dart-reach bench``, ``recording_overhead``). Timelines: ``step``
(control step, 0.1 s) and ``sim_time`` (s).

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

The run-level ``training.rrd`` holds best/mean/min fitness per phase and replication on the
timeline ``generation``.
"""

from __future__ import annotations

import functools
import os
import socket
import subprocess
import sys
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import polars as pl
import rerun as rr
import rerun.blueprint as rrb
from rerun import bindings as rerun_bindings
from rerun.chunk import RrdReader

from ..measures import metrics
from ..model.ctrnn import MOTOR_NAMES, N_HIDDEN, OFFSET, PROPRIO, SIGHT, TOUCH, TOUCH_NAMES
from ..files import atomic_write
from ..model.icub import HAND_SEGMENTS
from ..model.task import Senses, TrialData
from .robot_model import RobotModel

APP_ID = "dart_reach"
#: Version of the entity layout, in every recording's properties (2: the five signal entities;
#: 3: one entity per panel, movement variability, the trial's measures, the pendulum).
LAYOUT = 3
XYZ = ("x", "y", "z")
JOINT_GROUP_NAMES = tuple(metrics.JOINT_GROUPS)

#: The time series of a trial: (entity, series names, the (T, n) array of a record). Each
#: entity is what one panel of the default layout shows (a few lines; every entity's column
#: carries its own copy of the timelines, ~6 kB and ~0.2 ms per trial). A series is read back
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
                                 for g in JOINT_GROUP_NAMES), lambda d: _variability(d)[:, :6]),
    ("variability/distance", ("hand_shoulder", "hand_ball"), lambda d: _variability(d)[:, 6:]),
)

#: The per-trial measures a recording carries in its property ``trial``.
MEASURES = ("fitness", "reached", "reached_inner", "grasped", "first_touch_s",
            "first_touch_inner_s", "first_grasp_s", "speed", "speed_peak", "speed_final",
            "straightness", "straightness_onset", "movement_units", "var_elbow", "var_shoulder",
            "var_trunk", "hand_shoulder_mean", "hand_shoulder_cv", "elbow_freezing",
            "hand_ball_initial", "hand_ball_min", "approach", "heading", "hand_path",
            "hand_amplitude", "babbling_freq_hz", "babbling_share", "babbling",
            "anticipatory_grasp", "grasp_lead_s", "palm_up_swipe", "diverged")


def _variability(data: TrialData) -> np.ndarray:
    """(T, 8): window and cumulative variability per joint group, hand-shoulder and
    hand-ball distance (``metrics``)."""
    v = metrics.variability_over_time(data.joints)
    return np.stack([v[f"{kind}/{g}"] for kind in ("window", "cumulative")
                     for g in JOINT_GROUP_NAMES]
                    + [metrics.hand_shoulder_distance(data.hand, data.shoulder),
                       metrics.hand_ball_distance(data.hand, data.ball)], axis=1)


_GREY, _RED, _HAND_COLOUR = (170, 170, 180, 255), (230, 40, 40, 255), (40, 120, 230, 255)
_TOUCH, _STRING = (255, 200, 0, 255), (90, 90, 90, 255)
#: The ball of a ball-absent trial (``Senses.NO_BALL``): drawn faint where it would hang.
_ABSENT = (230, 40, 40, 50)


class RecordingError(ValueError):
    """A .rrd file is missing, truncated, or not a recording this version can read."""


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


# ------------------------------------------------------------------------------ blueprints
#: Qualitative colours of the lines of one panel (matplotlib's tab10): a panel never shows
#: more than ten lines, and its lines never share a colour.
_PALETTE = ((31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
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
        out[e] = [_PALETTE[(k + i) % len(_PALETTE)] for i in range(len(names[e]))]
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


@functools.cache
def _series_names(names: tuple[str, ...]) -> rr.SeriesLines:
    """The static series names of an entity (built once: ~0.1 ms each)."""
    return rr.SeriesLines(names=list(names))


# ------------------------------------------------------------------------------ writing
def trial_rrd(data: TrialData, info: TrialInfo, model: RobotModel, dt: float = 0.1,
              blueprint: bool = True, measures: dict | None = None) -> bytes:
    """The .rrd bytes of one trial (only its ``steps_run`` steps). With ``blueprint`` the file
    carries the default layout (``trial_blueprint``); that costs ~2.5 ms, a quarter of the
    recording's time, so the post-evaluation writes the layout once beside its recordings
    instead (``write_blueprint``). ``measures``: the trial's ``metrics.trial_metrics`` if
    already computed; the recording's property ``trial`` holds those of ``MEASURES`` beside the
    trial's ``TrialInfo``."""
    return encoded(info.name(),
                    lambda rec: _send_trial(rec, data, info, model, dt, blueprint, measures))


def _send_trial(rec: rr.RecordingStream, data: TrialData, info: TrialInfo, model: RobotModel,
                dt: float, blueprint: bool, measures: dict | None) -> None:
    """Send one trial to ``rec`` (``trial_rrd``)."""
    T = data.steps_run
    if blueprint:
        _send_blueprint(rec, trial_blueprint())
    rec.send_recording_name(info.name())
    measures = measures if measures is not None else metrics.trial_metrics(data, dt)
    rec.send_property("trial", rr.AnyValues(layout=LAYOUT, **asdict(info),
                                            **{m: measures[m] for m in MEASURES}))
    send_static(rec, info, model)
    send_rows(rec, data, model, dt, 0, T)
    # the pendulum's fixed pivot above the ball's start; the whole paths of hand and ball
    rec.log("world/pendulum/pivot", rr.Points3D([_pivot(data, model)], radii=0.006,
                                                colors=[_STRING]), static=True)
    rec.log("world/paths", _paths(data, T), static=True)


def send_static(rec: rr.RecordingStream, info: TrialInfo, model: RobotModel) -> None:
    """What a trial's recording holds for all time: series names, the scene's frame, the
    robot's box sizes, the round things' sizes and colours, the string's style."""
    for entity, names, _ in SIGNALS:
        rec.log(entity, _series_names(tuple(names)), static=True)
    # the 3D scene (the iCub root frame: +x backward, +y right, +z up)
    rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    rec.log("world/robot", rr.Boxes3D(half_sizes=model.box_half, fill_mode="solid"),
            static=True)
    # round things, one entity: the head's spheres, the ball, the palm point
    radii = np.concatenate([model.sphere_radius, [model.ball_radius, 0.008]])
    rec.log("world/spheres", rr.Ellipsoids3D(
        half_sizes=np.repeat(radii[:, None], 3, 1), fill_mode="solid",
        colors=[_GREY] * len(model.sphere_radius) + [
            _ABSENT if info.senses == Senses.NO_BALL.value else _RED, _HAND_COLOUR],
        labels=["head"] * len(model.sphere_radius) + ["ball", "palm"], show_labels=False),
        static=True)
    rec.log("world/pendulum/string", rr.LineStrips3D.from_fields(radii=0.0015,
                                                                  colors=[_STRING]),
            static=True)


def _pivot(data: TrialData, model: RobotModel) -> np.ndarray:
    return np.asarray(data.ball_start, float) + [0.0, 0.0, model.string_length]


def _paths(data: TrialData, stop: int) -> rr.LineStrips3D:
    return rr.LineStrips3D([data.hand[:stop], data.ball[:stop]], radii=0.002,
                           colors=[_HAND_COLOUR, _RED], labels=["hand path", "ball path"])


def send_rows(rec: rr.RecordingStream, data: TrialData, model: RobotModel, dt: float,
              start: int, stop: int, first: int = 0) -> None:
    """Send rows ``start``..``stop`` of a trial's record: every signal and the scene's poses,
    at steps ``first + start``.. of the timelines (``first``: where a live stream's episode
    begins)."""
    T = stop - start
    steps = np.arange(start, stop) + first
    index = [rr.TimeColumn("step", sequence=steps), rr.TimeColumn("sim_time", duration=steps * dt)]
    for entity, names, get in SIGNALS:
        values = np.asarray(get(data)[start:stop], dtype=float)
        rec.send_columns(entity, indexes=index, columns=rr.Scalars.columns(scalars=values))
    centres, quats, spheres = model.shape_poses(data.dofs[start:stop])
    nb = centres.shape[1]
    touching = np.zeros((T, nb), bool)
    on_hand = model.box_segment >= 0
    touching[:, on_hand] = data.contacts[start:stop][:, model.box_segment[on_hand]]
    colours = np.where(touching[..., None], _TOUCH, _GREY).astype(np.uint8).reshape(-1, 4)
    rec.send_columns("world/robot", indexes=index, columns=rr.Boxes3D.columns(
        centers=centres.reshape(-1, 3), quaternions=quats.reshape(-1, 4),
        colors=colours).partition([nb] * T))
    n_round = len(model.sphere_radius) + 2
    rec.send_columns("world/spheres", indexes=index, columns=rr.Ellipsoids3D.columns(
        centers=np.concatenate([spheres, data.ball[start:stop, None],
                                data.hand[start:stop, None]], axis=1)
        .reshape(-1, 3)).partition([n_round] * T))
    # the pendulum's string, from its fixed pivot to the ball
    strings = np.stack([np.broadcast_to(_pivot(data, model), (T, 3)), data.ball[start:stop]],
                       axis=1)
    rec.send_columns("world/pendulum/string", indexes=index,
                     columns=rr.LineStrips3D.columns(strips=strings))  # (T, 2, 3): numpy path


# ------------------------------------------------------------------------------ live
def live_stream(name: str, target: str | Path | None = None,
                spawn: bool = True) -> tuple[rr.RecordingStream, str]:
    """A recording stream for trials sent a step at a time (``send_live_step``), with the
    trial layout, and a line saying where it goes. ``target``: a viewer's gRPC URL
    (``rerun+http://HOST:PORT/proxy``; ``rerun`` alone listens at port 9876); a path (an .rrd
    file the stream is written to as it goes); None: a viewer spawned on this machine with
    ``spawn`` (where there is a display), else a gRPC server in this process on a free port,
    which buffers the stream until a viewer connects to it (``rerun --connect URL``)."""
    rec = rr.RecordingStream(APP_ID, recording_id=name, send_properties=False)
    if target is None and spawn:
        rec.spawn(hide_welcome_screen=True)
        where = "a Rerun viewer spawned on this machine (port 9876)"
    elif target is None:
        with socket.socket() as probe:  # a free port: 9876 may be another viewer's
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        url = rec.serve_grpc(grpc_port=port)
        where = (f"no display here: serving the episodes at {url}; watch them with "
                 f"`rerun --connect {url}` (from another machine: through an SSH tunnel to "
                 f"port {port})")
    elif str(target).startswith(("rerun://", "rerun+http://", "rerun+https://", "http://")):
        rec.connect_grpc(str(target))
        where = f"the Rerun viewer at {target}"
    else:
        rec.save(Path(target))
        where = f"the recording {target} (open it with `rerun {target}`)"
    _send_blueprint(rec, trial_blueprint())
    rec.send_recording_name(name)
    return rec, where


def send_live_step(rec: rr.RecordingStream, data: TrialData, info: TrialInfo,
                   model: RobotModel, dt: float, row: int, first: int = 0) -> None:
    """Send row ``row`` of a trial in progress to a live stream (``live_stream``), at step
    ``first + row`` of its timelines (``first``: where this trial begins in a stream that
    holds several one after another). Row 0 also sends what the trial holds for all its
    steps (``first`` 0: as static; later trials: at their first step)."""
    if row == 0:
        if first == 0:
            send_static(rec, info, model)
        rec.set_time("step", sequence=first)
        rec.set_time("sim_time", duration=first * dt)
        rec.log("world/pendulum/pivot", rr.Points3D([_pivot(data, model)], radii=0.006,
                                                    colors=[_STRING]))
    send_rows(rec, data, model, dt, row, row + 1, first)
    rec.set_time("step", sequence=first + row)
    rec.set_time("sim_time", duration=(first + row) * dt)
    rec.log("world/paths", _paths(data, row + 1))


def encoded(recording_id: str, send) -> bytes:
    """The .rrd bytes of what ``send(rec)`` sends to a new recording ``recording_id``. A rerun
    0.41 stream keeps its two threads (batcher, sink) until it is disconnected or cleaned up
    as an orphan: without the clean-up here and ``_send_blueprint`` every recording left two
    threads in its process and every layout two more (docs/changelog.md, 2026-11-27)."""
    rec = rr.RecordingStream(APP_ID, recording_id=recording_id, send_properties=False)
    stream = rec.binary_stream()
    send(rec)
    out = stream.read()
    rec.disconnect()
    del rec, stream
    rerun_bindings.flush_and_cleanup_orphaned_recordings()
    return out or b""


def _send_blueprint(rec: rr.RecordingStream, blueprint: rrb.Blueprint) -> None:
    """``rec.send_blueprint(blueprint)``, whose blueprint stream is never disconnected, with
    it disconnected: rerun 0.41's own steps (``create_in_memory_blueprint``) through the
    private names they use, held still by the pin on rerun's minor version."""
    stream = rr.RecordingStream._from_native(rerun_bindings.new_blueprint(
        application_id=APP_ID, make_default=False, make_thread_default=False,
        default_enabled=True))
    try:
        stream.set_time("blueprint", sequence=0)
        blueprint._log_to_stream(stream)
        rerun_bindings.send_blueprint(stream.memory_recording().storage, True, True,
                                      recording=rec.to_native())  # active, default
    finally:
        stream.disconnect()


def training_rrd(stats: pl.DataFrame, run_name: str) -> bytes:
    """The .rrd bytes of a run's fitness statistics (``generations.parquet``) on the timeline
    ``generation``, counted from the start of each condition (a phase's generations follow its
    predecessor's). One entity and one panel per condition and phase
    (``<condition>/<phase>``), with the series ``best rep<r>``, ``mean rep<r>`` and ``min
    rep<r>`` of each replication: a replication has one colour, its best line is thick, its
    mean thin, its min hidden (shown from the legend)."""
    return encoded(f"training {run_name}", lambda rec: _send_training(rec, stats, run_name))


def _send_training(rec: rr.RecordingStream, stats: pl.DataFrame, run_name: str) -> None:
    """Send a run's fitness statistics to ``rec`` (``training_rrd``)."""
    rec.send_recording_name(f"training {run_name}")
    rec.send_property("run", rr.AnyValues(layout=LAYOUT, run=run_name))
    views = []
    for (condition,), rows in stats.sort("condition").group_by("condition", maintain_order=True):
        offset = 0
        for phase in rows["phase"].unique(maintain_order=True):
            p = rows.filter(pl.col("phase") == phase).sort("generation", "replication")
            reps = p["replication"].unique().sort().to_list()
            wide = p.pivot("replication", index="generation", values=["best", "mean", "min"],
                           sort_columns=True)
            names, columns, colours, widths, visible = [], [], [], [], []
            for kind, width in (("best", 2.5), ("mean", 1.0), ("min", 1.0)):
                for i, r in enumerate(reps):
                    names.append(f"{kind} rep{r}")
                    columns.append(wide[f"{kind}_{r}"])
                    colours.append(_PALETTE[i % len(_PALETTE)])
                    widths.append(width)
                    visible.append(kind != "min")
            entity = f"{condition}/{phase}"
            rec.log(entity, rr.SeriesLines(names=names, colors=colours, widths=widths,
                                           visible_series=visible), static=True)
            rec.send_columns(entity, indexes=[rr.TimeColumn(
                "generation", sequence=wide["generation"].to_numpy() + offset)],
                columns=rr.Scalars.columns(scalars=np.stack(
                    [c.to_numpy().astype(float) for c in columns], axis=1)))
            offset += int(p["generation"].max())
            views.append(rrb.TimeSeriesView(name=f"{condition}: {phase}", origin=entity,
                                            plot_legend=rrb.Corner2D.LeftTop))
    _send_blueprint(rec, rrb.Blueprint(rrb.Grid(*views) if views else rrb.Vertical(),
                                       rrb.TimePanel(timeline="generation")))


def write_blueprint(path: Path) -> Path:
    """Save the default trial layout as a blueprint file (``.rbl``): ``rerun TRIAL.rrd
    PATH.rbl`` opens a recording with it."""
    def save(tmp: Path) -> None:
        trial_blueprint().save(APP_ID, str(tmp))
    return atomic_write(path, save)


def write_rrd(path: Path, content: bytes) -> Path:
    """Write .rrd bytes atomically (a reader sees the old file or the new one, never half)."""
    return atomic_write(path, lambda p: p.write_bytes(content))


# ------------------------------------------------------------------------------ reading
def _chunks(path: Path):
    path = Path(path)
    if path.is_dir():
        raise RecordingError(f"{path}: a directory, not a recording (.rrd file)")
    if not path.is_file():
        raise RecordingError(f"{path}: no such recording")
    try:
        with warnings.catch_warnings():
            # Every file this package writes ends with a footer; rerun only warns without one.
            warnings.filterwarnings("error", message=".*no footer", category=Warning)
            reader = RrdReader(str(path))
        if not reader.recordings():
            raise RecordingError(f"{path}: holds no recording")
        return list(reader.stream().to_chunks())
    except RecordingError:
        raise
    except Warning:
        raise RecordingError(f"{path}: truncated .rrd file (its footer is missing)") from None
    except Exception as exc:  # rerun raises its own error types for damaged files
        raise RecordingError(f"{path}: truncated or damaged .rrd file "
                             f"({_first_line(exc)})") from None


def _first_line(exc: Exception) -> str:
    return (str(exc).strip().splitlines() or [type(exc).__name__])[0]


def read_properties(path) -> dict:
    """The recording properties of a .rrd file written by this package, as a dict."""
    props = {}
    for chunk in _chunks(path):
        if chunk.is_static and chunk.entity_path.startswith("/__properties/"):
            batch = pl.from_arrow(chunk.to_record_batch())
            for col in batch.columns:
                if ":" not in col and not col.startswith("rerun."):
                    value = batch[col][0]
                    props[col] = value[0] if isinstance(value, pl.Series) else value
    return props


def read_rrd(path) -> pl.DataFrame:
    """A recording's time series as a polars table: one row per time point, the timeline
    columns (``step`` and ``sim_time`` in s for a trial, ``generation`` for ``training.rrd``)
    and one column per series, named ``<entity>/<series>`` (``"network/hidden/h3"``)."""
    path = Path(path)
    chunks = _chunks(path)
    names: dict[str, list[str]] = {}
    for c in chunks:
        if c.is_static:
            batch = c.to_record_batch()
            if "SeriesLines:names" in batch.schema.names:
                names[c.entity_path.lstrip("/")] = batch.column("SeriesLines:names")[0].as_py()
    frames: dict[str, list[pl.DataFrame]] = {}
    for c in chunks:
        entity = c.entity_path.lstrip("/")
        if c.is_static or entity not in names:
            continue
        batch = pl.from_arrow(c.to_record_batch())
        if "Scalars:scalars" not in batch.columns:
            continue
        timelines = sorted((c for c in batch.columns if ":" not in c and
                            not c.startswith("rerun.")), key=lambda c: (c != "step", c))
        times = {c: batch[c].dt.total_nanoseconds() / 1e9 if batch[c].dtype == pl.Duration
                 else batch[c].cast(pl.Int64) for c in timelines}
        cols = [f"{entity}/{n}" for n in names[entity]]
        values = np.array(batch["Scalars:scalars"].to_list(), float).reshape(
            batch.height, len(cols))
        frames.setdefault(entity, []).append(pl.DataFrame(
            {**times, **{n: values[:, i] for i, n in enumerate(cols)}}))
    if not frames:
        raise RecordingError(f"{path}: holds no time series written by dart_reach")
    table = None
    for parts in frames.values():
        part = pl.concat(parts)
        if table is None:
            table = part
        else:
            on = [c for c in part.columns if c in table.columns]
            table = table.join(part, on=on, how="full", coalesce=True)
    return table.sort(table.columns[0])


def verify(*paths) -> None:
    """Check .rrd files with rerun's own verifier (``rerun rrd verify``); raise
    ``RecordingError`` unless every one of them passes. (The verifier skips a file that is not
    an .rrd at all without failing: the count of verified files is checked too.)"""
    exe = Path(sys.executable).parent / "rerun"
    cmd = [str(exe) if exe.exists() else "rerun", "rrd", "verify", *map(str, paths)]
    out = subprocess.run(cmd, capture_output=True, text=True,
                         env=dict(os.environ, RERUN_ANALYTICS="0"))
    text = out.stdout + out.stderr
    n = len(paths)
    if out.returncode != 0 or f"{n} file{'s' if n != 1 else ''} verified without error" not in text:
        lines = [line for line in text.strip().splitlines() if line.strip()]
        raise RecordingError(f"{paths[0] if n == 1 else f'{n} files'}: rerun rrd verify failed: "
                             f"{' / '.join(lines[-2:])}")
