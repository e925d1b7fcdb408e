"""Recordings of post-evaluation trials, made again on demand.

A post-evaluation records few trials (``Record``), and the committed results hold none: a
recording is 0.3-0.45 MB. But every trial is deterministic (fixed positions, the same start
state), so the trial of any row of a results table can be run again and recorded, at the path
it would have had (``RobotJob.recording_path``; recordings are git-ignored). ``recording``
returns the file of a row, from disk when it is there; the figures that draw trajectories
(Figs. 6 and 8) read their trials through it, so they work on a fresh clone from the committed
results alone.
"""

from __future__ import annotations

from pathlib import Path

from .systematic import BLUEPRINT, run_robot, stored_robot_job
from ..evolution.rundir import RunDirectory
from ..model.world import POINTS_PER_SECTOR
from ..recording.rrd import write_blueprint, write_rrd


def recording(run_dir, row: dict, cache=None) -> Path:
    """The .rrd file of the post-evaluation trial of ``row`` (a row of the evaluation table,
    or of the baseline's): its recording when it exists, else the trial run again and recorded
    at its standard path under ``cache`` (a directory; default ``run_dir``: then the run keeps
    it, beside the post-evaluation's own recordings). With a ``cache``, nothing is written
    under ``run_dir``."""
    run_dir = Path(run_dir)
    cache = run_dir if cache is None else Path(cache)
    if row.get("recording") and (run_dir / row["recording"]).is_file():
        return run_dir / row["recording"]
    run = RunDirectory.open(run_dir)
    job = stored_robot_job(run, row["phase_key"], row["senses"], row["replication"],
                           row["rank"], baseline=bool(row.get("baseline")),
                           positions=(row["trial"],), record=True)
    path = cache / job.recording_path(row["trial"], row["trial"] // POINTS_PER_SECTOR)
    if path.is_file():  # made again before
        return path
    _, (content,) = run_robot(job)
    write_rrd(path, content)
    if not (cache / BLUEPRINT).exists():
        write_blueprint(cache / BLUEPRINT)
    return path
