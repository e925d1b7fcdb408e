"""Watch an evolved robot in seconds (``dart-reach watch``): one trial of a shipped robot
(``robots.robots``) or of a trained run's best robot, recorded with the trial layout and opened
in the Rerun viewer where there is a display; where none opens, saved for later and drawn
by the numpy camera (``replay.write_pictures``: a strip of a few instants and an animated GIF
beside the recording, a few seconds more).

One trial, in this process, no pool: about a second of simulation for 20 simulated seconds,
plus the recording.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..errors import UsageError
from ..evolution.backends import worker_trial
from ..evolution.conditions import load_condition
from ..evolution.genome import as_groups, decode
from ..evolution.rundir import RunDirectory
from ..evolution.settings import Settings, trial_config
from ..measures import metrics
from ..model.task import Senses, network_for
from ..model.world import N_SECTORS, POINTS_PER_SECTOR, SectorConfig, WorldConfig
from ..recording.rrd import RobotModel, TrialInfo, trial_rrd, write_blueprint, write_rrd
from ..robots import index, robots
from .headless import rerun_binary
from .replay import Poses, write_pictures

#: Phases of the standard condition in developmental order.
PHASES = ("pre", "gross", "fine")
#: The budget advised for training a robot to watch when none ships: ``make demo``'s, a few
#: minutes on 2 cores (the condition's own budget is 500 generations per phase x 10
#: replications, days).
SMALL_TRAINING = ("--generations", "3", "--replications", "2", "--trials", "6")


@dataclass(frozen=True)
class Watched:
    """What ``watch`` did: the recording (``.rrd``) and its layout (``.rbl``), which robot
    (one line), the trial's measures (``metrics.trial_metrics``), the process id of the
    viewer it started (None: none started; ``open_command`` opens the files), and the
    pictures drawn where none started (the strip ``.png`` and the animation ``.gif``)."""

    recording: Path
    layout: Path
    robot: str
    measures: dict = field(repr=False)
    viewer_pid: int | None = None
    pictures: tuple[Path, ...] = ()

    @property
    def open_command(self) -> list[str]:
        """The viewer on the files, through this Python (``python -m rerun``): it runs
        whether or not its virtual environment is active."""
        return [sys.executable, "-m", "rerun", str(self.recording), str(self.layout)]


def display_available(environ=None) -> bool:
    """True where a viewer window can open: on Linux and other X11/Wayland systems when
    ``DISPLAY`` or ``WAYLAND_DISPLAY`` is set; always on macOS and Windows."""
    environ = os.environ if environ is None else environ
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(environ.get("DISPLAY") or environ.get("WAYLAND_DISPLAY"))


@dataclass(frozen=True, eq=False)
class _Choice:
    """The robot to watch: genome, condition name, Phase, Settings, replication, one line."""

    genome: object
    condition: str
    phase: object
    settings: object
    replication: int
    text: str


def _longest_trained(robots: list) -> list:
    """The robots of one shipped file (one run's condition and phase) among ``robots``: the
    file whose run trained longest (most generations, then most replications, then the last
    file name), so that two files' replications and ranks are never mixed."""
    by_file: dict = {}
    for r in robots:
        by_file.setdefault(r.source, []).append(r)

    def size(source):
        b = by_file[source][0].provenance.get("budget") or {}
        return b.get("generations") or 0, b.get("replications") or 0, source
    return by_file[max(by_file, key=size)]


def _shipped(phase, condition, replication, rank, shipped=None) -> _Choice:
    """The best shipped robot asked for (of the run named ``shipped``, default the
    longest-trained run that ships the phase)."""

    wanted = robots(phase, condition, run=shipped)
    if phase is None:  # the most developed phase that ships
        for name in reversed(PHASES):
            if any(r.phase == name for r in wanted):
                wanted = [r for r in wanted if r.phase == name]
                break
    if not wanted:
        names = [p.name for p in load_condition(condition).phases]
        if phase is not None and phase not in names:
            raise UsageError(f"phase={phase!r}: {condition} has no phase {phase!r} (its "
                             f"phases: {', '.join(names)})",
                             cli=f"{phase}: {condition} has no phase {phase!r} (its phases: "
                                 f"{', '.join(names)})")
        files = index()
        runs = sorted({r["run"] for r in files if r["run"] is not None})
        if shipped is not None and shipped not in runs:
            raise UsageError(f"shipped={shipped!r}: no such shipped run (shipped runs: "
                             f"{', '.join(runs)})", cli=f"--shipped {shipped}: no such shipped "
                                                        f"run (shipped runs: {', '.join(runs)})")
        ships = ", ".join(sorted({f"{r['condition']}/{r['phase']}" for r in files
                                  if shipped is None or r["run"] == shipped}))
        asked = (f"{condition}/{phase}" if phase else condition) + (
            f" in shipped run {shipped!r}" if shipped else "")
        out = f"recordings/{condition}-small"
        train = ["dart-reach", "train", condition, *SMALL_TRAINING, "--out", out]
        again = ["dart-reach", "watch", *([phase] if phase else []), "--condition", condition,
                 "--run", out]
        raise UsageError(
            f"no shipped robot of {asked}: only {ships} ships; train one at a small budget "
            f"(dart_reach.train, as in make demo) and watch it with run=RUN_DIR",
            cli=f"no shipped robot of {asked}: only {ships} ships; train one at a small "
                f"budget (a few minutes on 2 cores): {shlex.join(train)}, then watch it: "
                f"{shlex.join(again)}")
    wanted = _longest_trained(wanted)
    if replication is not None:
        have = sorted({r.replication for r in wanted})
        wanted = [r for r in wanted if r.replication == replication]
        if not wanted:
            raise UsageError(f"replication={replication}: the shipped robots come from "
                             f"replications {have}", cli=f"--replication {replication}: the "
                                                         f"shipped robots come from "
                                                         f"replications {have}")
    else:
        best = wanted[0].replication
        wanted = [r for r in wanted if r.replication == best]
    wanted = sorted(wanted, key=lambda r: r.rank)
    if rank >= len(wanted):
        raise UsageError(f"rank={rank}: {len(wanted)} robots ship for that replication",
                         cli=f"--rank {rank}: {len(wanted)} robots ship for that replication")
    robot = wanted[rank]
    phases = {p.name: p for p in load_condition(robot.condition).phases}
    ph = phases[robot.phase]
    stored = robot.provenance.get("phase") or {}
    if ([g.value for g in ph.free_groups] != stored.get("free_groups")
            or ph.acuity != stored.get("acuity") or ph.reflexes != stored.get("reflexes")):
        raise ValueError(f"{robot.source}: its phase differs from the shipped condition "
                         f"{robot.condition}'s {robot.phase} (made by another version)")
    budget = robot.provenance.get("budget") or {}
    world = WorldConfig(physics_dt=float(budget.get("physics_dt", 0.02)))
    if "sectors" in budget:  # the scene the robots evolved in (docs/model/scene.md)
        world = replace(world, sectors=SectorConfig(**budget["sectors"]))
    settings = Settings(replications=1, steps=int(budget.get("steps", 200)), world=world)
    return _Choice(robot.genome, robot.condition, ph, settings, robot.replication,
                   "shipped robot " + robot.describe())


def _trained(run_dir, phase, condition, replication, rank) -> _Choice:
    """A trained run's robot."""

    run = RunDirectory.open(run_dir)
    names = [c.name for c in run.conditions]
    if condition is None or (condition == "standard" and condition not in names):
        cond = run.conditions[0]
    elif condition in names:
        cond = run.conditions[names.index(condition)]
    else:
        raise UsageError(f"condition={condition!r}: {run.out} trained {', '.join(names)}",
                         cli=f"--condition {condition}: {run.out} trained {', '.join(names)}")
    trained = [p for p in cond.phases if run.final_path(p).exists()]
    if not trained:
        raise UsageError(f"{run.out}: no phase of {cond.name} is trained to the end yet")
    if phase is None:
        ph = trained[-1]
    else:
        match = [p for p in cond.phases if p.name == phase]
        if not match:
            raise UsageError(f"{run.out}: condition {cond.name} has no phase {phase!r} (it has "
                             f"{', '.join(p.name for p in cond.phases)})")
        ph = match[0]
        if ph not in trained:
            raise UsageError(f"{run.out}: {cond.name}/{phase} is not trained to the end yet")
    genomes, fitness = run.load_final(ph)
    r = int(np.argmax(fitness[:, 0])) if replication is None else replication
    if not 0 <= r < genomes.shape[0]:
        raise UsageError(f"replication={r}: the run has replications 0..{genomes.shape[0] - 1}",
                         cli=f"--replication {r}: the run has replications "
                             f"0..{genomes.shape[0] - 1}")
    if not 0 <= rank < genomes.shape[1]:
        raise UsageError(f"rank={rank}: the population has {genomes.shape[1]} robots",
                         cli=f"--rank {rank}: the population has {genomes.shape[1]} robots")
    text = (f"trained robot {cond.name}/{ph.name} replication {r} rank {rank} (lifetime "
            f"fitness {fitness[r, rank]:.4f}) of {run.out}")
    return _Choice(genomes[r, rank], cond.name, ph, run.settings, r, text)


def _files(rrd: Path) -> tuple[Path, ...]:
    """The files a watched trial may write: the recording, its layout and its pictures."""
    return tuple(rrd.with_suffix(suffix) for suffix in (".rrd", ".rbl", ".png", ".gif"))


def _output(out, default: Path) -> Path:
    """The recording to write, checked before the trial runs: ``out``, refused where it does
    not end in .rrd or where it or a file beside it (``_files``) exists; without ``out``,
    ``default``, or where that is taken the first free ``<name>-2.rrd``, ``<name>-3.rrd``, ...
    Nothing is ever overwritten."""
    if out is None:
        candidate, n = default, 1
        while any(p.exists() for p in _files(candidate)):
            n += 1
            candidate = default.with_name(f"{default.stem}-{n}.rrd")
        return candidate
    out = Path(out)
    if out.suffix != ".rrd":
        raise UsageError(f"out must end in .rrd, got {out}",
                         cli=f"--out must end in .rrd, got {out}")
    taken = [p for p in _files(out) if p.exists()]
    if taken:
        raise FileExistsError(f"{taken[0]} exists; choose another recording (nothing is "
                              f"overwritten)")
    return out


def watch(phase: str | None = None, condition: str | None = "standard",
          replication: int | None = None, rank: int = 0, sector: int = 4,
          senses: str = "normal", run=None, out=None, viewer: bool | None = None,
          shipped: str | None = None) -> Watched:
    """Run one trial of an evolved robot with the ball at the centre of ``sector`` (0..8; the
    post-evaluation's trial 5 x sector) and record it with the trial layout.

    The robot: with ``run`` (a run directory), the best robot (``rank`` 0) of the best
    replication (or of ``replication``) of ``phase`` of ``condition`` (default: the run's last
    trained phase; the run's first condition when it lacks ``condition``); without, the
    best shipped robot of ``phase`` of ``condition`` (``robots.robots``; default: the most
    developed phase that ships) from the shipped run named ``shipped`` (``robots.index()``'s
    ``run``; default: the run that trained that phase longest). ``senses``: normal, no-touch,
    no-sight or nothing (Fig. 9).

    Writes ``out`` (default ``recordings/watch/<condition>-<phase>-sector<K>.rrd``, made
    with its folder, or ``...-2.rrd`` and on where taken) and its layout beside it (``.rbl``);
    an ``out`` that exists, or whose layout or pictures do, is refused before the trial runs.
    ``viewer``: True starts the Rerun viewer on them, False does not, None (default) starts
    it where a display is available.
    Where no viewer starts, the numpy camera draws the trial beside them: a strip of a few
    instants (``.png``) and the whole trial at real time (``.gif``).
    """

    if phase is not None and not isinstance(phase, str):
        raise UsageError(f"phase must be a phase name such as 'pre', got {phase!r}")
    if not (isinstance(sector, int) and 0 <= sector < N_SECTORS):
        raise UsageError(f"sector must be 0..{N_SECTORS - 1}, got {sector!r}",
                         cli=f"--sector must be 0..{N_SECTORS - 1}, got {sector!r}")
    try:
        how = Senses(senses)
    except ValueError:
        choices = ", ".join(s.value for s in Senses)
        raise UsageError(f"senses must be one of {choices}, got {senses!r}",
                         cli=f"--senses must be one of {choices}, got {senses!r}") from None
    if run is not None and shipped is not None:
        raise UsageError("give run (a trained run directory) or shipped (a shipped run's "
                         "name), not both", cli="give --run or --shipped, not both")
    robot = (_trained(run, phase, condition, replication, rank) if run is not None
             else _shipped(phase, condition, replication, rank, shipped))
    ph, settings = robot.phase, robot.settings
    out = _output(out, Path("recordings") / "watch"
                  / f"{robot.condition}-{ph.name}-sector{sector}.rrd")
    trial = replace(trial_config(ph, settings), senses=how)
    runner = worker_trial(settings.world, trial)
    world = runner.world
    k = POINTS_PER_SECTOR * sector  # the sector's centre among the 45 systematic points
    network = network_for(decode(robot.genome, as_groups(ph.free_groups)), trial)
    data = runner.run(network, sector, world.systematic_points()[k])
    measures = metrics.trial_metrics(data, settings.world.control_dt)
    out.parent.mkdir(parents=True, exist_ok=True)
    info = TrialInfo(robot.condition, ph.name, robot.replication, rank, sector, k,
                     "systematic", how.value)
    write_rrd(out, trial_rrd(data, info, RobotModel(world), settings.world.control_dt,
                             measures=measures))
    layout = write_blueprint(out.with_suffix(".rbl"))
    if viewer or (viewer is None and display_available()):
        binary = rerun_binary()
        if binary is None:
            raise RuntimeError("the rerun viewer is not installed (pip install rerun-sdk)")
        pid = subprocess.Popen([binary, str(out), str(layout)], start_new_session=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).pid
        return Watched(out, layout, robot.text, measures, pid)
    pictures = write_pictures(world, Poses.of_trial(data, settings.world.control_dt), out)
    return Watched(out, layout, robot.text, measures, pictures=pictures)
