"""Rerun recordings of trials and of training, and reading them back (with ``layout``, the
only modules that import rerun).

A trial is recorded after it has run, from its ``TrialData``, in the entity layout of
``layout``: its rows go as one Arrow record batch that rerun cuts into a chunk per entity, and
the chunks are written by rerun's chunk writer, with no recording stream, in less CPU time
than sending them entity by entity through rerun's archetypes to a stream
(docs/results/benchmarks.md: ``recording_overhead``, ``recording_parts``).
Timelines: ``step`` (control step, 0.1 s) and ``sim_time`` (s).

The run-level ``training.rrd`` holds best/mean/min fitness per phase and replication on the
timeline ``generation``.
"""

from __future__ import annotations

import functools
import os
import socket
import subprocess
import sys
import tempfile
import warnings
from dataclasses import asdict
from pathlib import Path

import numpy as np
import polars as pl
import pyarrow as pa
import rerun as rr
import rerun.blueprint as rrb
from rerun import bindings as rerun_bindings
from rerun.chunk import Chunk, LazyChunkStream, RrdReader

from ..measures import metrics
from .. import integrity
from ..model.task import Senses, TrialData
from .layout import LAYOUT, MEASURES, PALETTE, SIGNALS, TrialInfo, trial_blueprint
from .robot_model import RobotModel

APP_ID = "dart_reach"
_GREY, _RED, _HAND_COLOUR = (170, 170, 180, 255), (230, 40, 40, 255), (40, 120, 230, 255)
_TOUCH, _STRING = (255, 200, 0, 255), (90, 90, 90, 255)
#: The ball of a ball-absent trial (``Senses.NO_BALL``): drawn faint where it would hang.
_ABSENT = (230, 40, 40, 50)


class RecordingError(ValueError):
    """A .rrd file is missing, truncated, or not a recording this version can read."""


# ------------------------------------------------------------------------------ writing
def trial_rrd(data: TrialData, info: TrialInfo, model: RobotModel, dt: float = 0.1,
              blueprint: bool = True, measures: dict | None = None) -> bytes:
    """The .rrd bytes of one trial (only its ``steps_run`` steps). With ``blueprint`` the file
    carries the default layout (``trial_blueprint``); that costs a recording stream and a
    large part of the recording's time, so the post-evaluation writes the layout once beside
    its recordings instead (``write_blueprint``). ``measures``: the trial's
    ``metrics.trial_metrics`` if already computed; the recording's property ``trial`` holds
    those of ``MEASURES`` beside the trial's ``TrialInfo``."""
    chunks = trial_chunks(data, info, model, dt, measures)
    if blueprint:
        return streamed_rrd(info.name(), chunks, trial_blueprint())
    return chunks_rrd(info.name(), chunks)


def trial_chunks(data: TrialData, info: TrialInfo, model: RobotModel, dt: float,
                 measures: dict | None) -> list[Chunk]:
    """A trial's recording as chunks (``trial_rrd``): its name and property ``trial``, what it
    holds for all time, its rows, the pendulum's fixed pivot above the ball's start and the
    whole paths of hand and ball."""
    T = data.steps_run
    measures = measures if measures is not None else metrics.trial_metrics(data, dt)
    return [_static_chunk("/__properties", rr.archetypes.RecordingInfo(name=info.name())),
            Chunk.from_property("trial", _trial_property(info, measures)),
            *_static_chunks(model, info.senses), *row_chunks(data, model, dt, 0, T),
            _static_chunk("world/pendulum/pivot", _pivot_point(data, model)),
            _static_chunk("world/paths", _paths(data, T))]


def chunks_rrd(recording_id: str, chunks: list[Chunk]) -> bytes:
    """The .rrd bytes of the recording ``recording_id`` of ``chunks``, written by rerun's
    chunk writer: no recording stream and none of its threads; as cheap as ``streamed_rrd``
    on an idle machine, cheaper under load (docs/results/benchmarks.md,
    ``recording_parts``)."""
    with tempfile.TemporaryDirectory(prefix="dart-reach-rrd-") as tmp:
        path = Path(tmp) / "recording.rrd"
        LazyChunkStream.from_iter(chunks).write_rrd(path, application_id=APP_ID,
                                                    recording_id=recording_id)
        return path.read_bytes()


def streamed_rrd(recording_id: str, chunks: list[Chunk],
                 blueprint: rrb.Blueprint | None = None) -> bytes:
    """The .rrd bytes of the recording ``recording_id`` of ``chunks`` sent through a
    recording stream, with ``blueprint`` as its default layout (the chunk writer of
    ``chunks_rrd`` writes recordings only)."""
    def send(rec: rr.RecordingStream) -> None:
        if blueprint is not None:
            _send_blueprint(rec, blueprint)
        rr.send_chunks(chunks, recording=rec)
    return encoded(recording_id, send)


def _trial_property(info: TrialInfo, measures: dict) -> rr.AnyValues:
    """The recording's property ``trial``: the layout's version, the ``TrialInfo`` and the
    trial's ``MEASURES``, each a one-value column of the type ``rr.AnyValues`` would infer
    (bool, int64, float64, string; None left out), built directly: its inference costs time
    for every value (docs/results/benchmarks.md, the recording's parts)."""
    values = {"layout": LAYOUT, **asdict(info), **{m: measures[m] for m in MEASURES}}
    return rr.AnyValues(**{name: _one_value(v) for name, v in values.items() if v is not None})


def _one_value(value) -> pa.Array:
    for kinds, arrow in (((bool, np.bool_), pa.bool_()), ((int, np.integer), pa.int64()),
                         ((float, np.floating), pa.float64()), ((str,), pa.string())):
        if isinstance(value, kinds):
            return pa.array([value], arrow)
    raise RecordingError(f"a trial's property cannot hold {value!r} ({type(value).__name__})")


def send_static(rec: rr.RecordingStream, info: TrialInfo, model: RobotModel) -> None:
    """What a trial's recording holds for all time: series names, the scene's frame, the
    robot's box sizes, the round things' sizes and colours, the string's style (built once
    per drawing model and sensory condition: ``_static_chunks``)."""
    rr.send_chunks(_static_chunks(model, info.senses), recording=rec)


@functools.lru_cache(maxsize=8)
def _static_chunks(model: RobotModel, senses: str) -> tuple[Chunk, ...]:
    """``send_static``'s chunks, one per entity. Converting an archetype to Arrow costs
    time (docs/results/benchmarks.md, the recording's parts); these 19 are the same in every
    trial of a process, so they are converted once and sent as they are (a chunk takes the
    identity of the recording it is sent to)."""
    parts = [(entity, rr.SeriesLines(names=list(names))) for entity, names, _ in SIGNALS]
    # the 3D scene (the iCub root frame: +x backward, +y right, +z up)
    parts.append(("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP))
    parts.append(("world/robot", rr.Boxes3D(half_sizes=model.box_half, fill_mode="solid")))
    # round things, one entity: the head's spheres, the ball, the palm point
    radii = np.concatenate([model.sphere_radius, [model.ball_radius, 0.008]])
    parts.append(("world/spheres", rr.Ellipsoids3D(
        half_sizes=np.repeat(radii[:, None], 3, 1), fill_mode="solid",
        colors=[_GREY] * len(model.sphere_radius) + [
            _ABSENT if senses == Senses.NO_BALL.value else _RED, _HAND_COLOUR],
        labels=["head"] * len(model.sphere_radius) + ["ball", "palm"], show_labels=False)))
    parts.append(("world/pendulum/string",
                  rr.LineStrips3D.from_fields(radii=0.0015, colors=[_STRING])))
    return tuple(_static_chunk(entity, archetype) for entity, archetype in parts)


def _static_chunk(entity: str, archetype) -> Chunk:
    """What ``rec.log(entity, archetype, static=True)`` sends: one row for all time."""
    return Chunk.from_columns(entity, [], [
        rr.ComponentColumn(b.component_descriptor(), b).partition([len(b.as_arrow_array())])
        for b in archetype.as_component_batches()])


def _pivot(data: TrialData, model: RobotModel) -> np.ndarray:
    return np.asarray(data.ball_start, float) + [0.0, 0.0, model.string_length]


def _pivot_point(data: TrialData, model: RobotModel) -> rr.Points3D:
    """The pendulum's fixed pivot, drawn."""
    return rr.Points3D([_pivot(data, model)], radii=0.006, colors=[_STRING])


def _paths(data: TrialData, stop: int) -> rr.LineStrips3D:
    return rr.LineStrips3D([data.hand[:stop], data.ball[:stop]], radii=0.002,
                           colors=[_HAND_COLOUR, _RED], labels=["hand path", "ball path"])


#: Entities sent per step beside ``SIGNALS``' (``send_rows``).
_SCENE_ROWS = ("world/robot", "world/spheres", "world/pendulum/string")


@functools.cache
def _row_schema() -> pa.Schema:
    """The Arrow schema of a trial's rows as one record batch: the timelines ``step`` and
    ``sim_time``, then a component column per entity, each with its entity path, in the
    order of ``SIGNALS`` and then ``_SCENE_ROWS``. The fields are rerun's own
    (``Chunk.from_columns``), built once."""
    index = [rr.TimeColumn("step", sequence=[0]), rr.TimeColumn("sim_time", duration=[0.0])]
    columns = [rr.Scalars.columns(scalars=np.zeros((1, len(names)))) for _, names, _ in SIGNALS]
    columns += [rr.Boxes3D.columns(centers=np.zeros((1, 3)), quaternions=[[0.0, 0, 0, 1]],
                                   colors=[_GREY]),
                rr.Ellipsoids3D.columns(centers=np.zeros((1, 3))),
                rr.LineStrips3D.columns(strips=np.zeros((1, 2, 3)))]
    fields = []
    for entity, cols in zip([e for e, _, _ in SIGNALS] + list(_SCENE_ROWS), columns):
        schema = Chunk.from_columns(entity, index, cols).to_record_batch().schema
        if not fields:
            fields = [schema.field("step"), schema.field("sim_time")]
        fields += [f.with_name(f"/{entity}:{f.name}").with_metadata(
            {**f.metadata, b"rerun:entity_path": f"/{entity}".encode()})
            for f in schema if f.metadata.get(b"rerun:kind") == b"data"]
    return pa.schema(fields)


def _arrow(values: np.ndarray, kind: pa.DataType) -> pa.Array:
    """``values`` as an Arrow array of type ``kind``, one element per index of the first
    axis: a list or fixed-size list takes the next axis as its items."""
    if pa.types.is_list(kind) or pa.types.is_fixed_size_list(kind):
        n, k = values.shape[:2]
        items = _arrow(values.reshape((n * k,) + values.shape[2:]), kind.value_type)
        if pa.types.is_fixed_size_list(kind):
            return pa.FixedSizeListArray.from_arrays(items, type=kind)
        return pa.ListArray.from_arrays(pa.array(np.arange(0, n * k + 1, k, dtype=np.int32)),
                                        items, type=kind)
    return pa.array(np.ascontiguousarray(values, dtype=kind.to_pandas_dtype()), type=kind)


def _rgba32(colours: np.ndarray) -> np.ndarray:
    """RGBA bytes (..., 4) as rerun's packed colours (0xRRGGBBAA)."""
    c = colours.astype(np.uint32)
    return (c[..., 0] << 24) | (c[..., 1] << 16) | (c[..., 2] << 8) | c[..., 3]


#: The robot's boxes drawn touching the ball, and not, as rerun's packed colours.
_TOUCH_RGBA32, _GREY_RGBA32 = _rgba32(np.array([_TOUCH, _GREY], np.uint8))


def send_rows(rec: rr.RecordingStream, data: TrialData, model: RobotModel, dt: float,
              start: int, stop: int, first: int = 0) -> None:
    """Send rows ``start``..``stop`` of a trial's record: every signal and the scene's poses,
    at steps ``first + start``.. of the timelines (``first``: where a live stream's episode
    begins)."""
    rr.send_chunks(row_chunks(data, model, dt, start, stop, first), recording=rec)


def row_chunks(data: TrialData, model: RobotModel, dt: float, start: int, stop: int,
               first: int = 0) -> list[Chunk]:
    """``send_rows``' chunks, one per entity: built from one record batch (``_row_schema``)
    that rerun cuts by entity, they hold what ``send_columns`` per entity would send, without
    a conversion through rerun's archetypes per entity."""
    T = stop - start
    steps = np.arange(start, stop) + first
    values = {f"/{entity}:Scalars:scalars": np.asarray(get(data)[start:stop], dtype=float)
              for entity, _, get in SIGNALS}
    centres, quats, spheres = model.shape_poses(data.dofs[start:stop])
    touching = np.zeros(centres.shape[:2], bool)
    on_hand = model.box_segment >= 0
    touching[:, on_hand] = data.contacts[start:stop][:, model.box_segment[on_hand]]
    values["/world/robot:Boxes3D:centers"] = centres
    values["/world/robot:Boxes3D:quaternions"] = quats
    values["/world/robot:Boxes3D:colors"] = np.where(touching, _TOUCH_RGBA32, _GREY_RGBA32)
    # the round things (the head's spheres, the ball, the palm point); the pendulum's string,
    # from its fixed pivot to the ball (one strip of two points a step)
    values["/world/spheres:Ellipsoids3D:centers"] = np.concatenate(
        [spheres, data.ball[start:stop, None], data.hand[start:stop, None]], axis=1)
    values["/world/pendulum/string:LineStrips3D:strips"] = np.stack(
        [np.broadcast_to(_pivot(data, model), (T, 3)), data.ball[start:stop]], axis=1)[:, None]
    schema = _row_schema()
    arrays = [rr.TimeColumn("step", sequence=steps).as_arrow_array(),
              rr.TimeColumn("sim_time", duration=steps * dt).as_arrow_array().cast(
                  schema.field("sim_time").type)]
    arrays += [_arrow(values[f.name], f.type) for f in list(schema)[2:]]
    return Chunk.from_record_batch(pa.RecordBatch.from_arrays(arrays, schema=schema))


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
        rec.log("world/pendulum/pivot", _pivot_point(data, model))
    send_rows(rec, data, model, dt, row, row + 1, first)
    rec.set_time("step", sequence=first + row)
    rec.set_time("sim_time", duration=(first + row) * dt)
    rec.log("world/paths", _paths(data, row + 1))


def encoded(recording_id: str, send) -> bytes:
    """The .rrd bytes of what ``send(rec)`` sends to a new recording ``recording_id``. A rerun
    0.41 stream keeps its two threads (batcher, sink) until it is disconnected or cleaned up
    as an orphan: without the clean-up here and ``_send_blueprint`` every recording left two
    threads in its process and every layout two more (measured; docs/changelog.md)."""
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
                    colours.append(PALETTE[i % len(PALETTE)])
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
    return integrity.write(path, save)


def write_rrd(path: Path, content: bytes) -> Path:
    """Write .rrd bytes atomically (a reader sees the old file or the new one, never half),
    in a run's ledger when it lies in a run (``integrity.write``)."""
    return integrity.write(path, lambda p: p.write_bytes(content))


# ------------------------------------------------------------------------------ reading
def _chunks(path: Path):
    path = Path(path)
    if path.is_dir():
        raise RecordingError(f"{path}: a directory, not a recording (.rrd file)")
    if not path.is_file():
        raise RecordingError(f"{path}: no such recording")
    integrity.verified(path)  # a recording of a run: as its ledger recorded it
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
