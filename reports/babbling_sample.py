"""The real trials on which the babbling detector is checked by eye (docs/model/measures.md,
"Validating the detector"): a seeded draw of 20 normal and 20 ball-absent post-evaluation
trials of ``FULL``'s snapshot 250, run again from the snapshot's genomes for their hand paths
(the trial is deterministic), stored as ``SAMPLE`` and plotted under codes that name neither
the robot, the condition nor any measure.

    python -m reports.babbling_sample .          # draw, run again, store, plot (~1 min)

The plots go to ``PLOTS`` (docs/results/babbling-detector/), the labels made from them to
``LABELS`` (by hand, before ``reports.babbling_detector`` is run)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import polars as pl

from dart_reach import integrity
from dart_reach.evolution.backends import worker_trial
from dart_reach.evolution.genome import as_groups, decode
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.files import write_parquet
from dart_reach.measures.contacts import first_touch
from dart_reach.model.task import network_for
from dart_reach.model.world import POINTS_PER_SECTOR
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import stored_robot_job

from .runs import FULL

#: The snapshot drawn from, the draw's seed, trials per condition and the conditions.
GENERATION, SEED, PER_CONDITION = 250, 2026, 20
CONDITIONS = ("normal", "no-ball")
SAMPLE = f"recordings/{FULL}/babbling-sample.parquet"
PLOTS = "docs/results/babbling-detector"
LABELS = f"recordings/{FULL}/babbling-labels.csv"
#: Trials per plot sheet.
PER_SHEET = 8


def draw(run_dir: Path) -> pl.DataFrame:
    """The sample: ``PER_CONDITION`` trials of each of ``CONDITIONS`` drawn without
    replacement by ``numpy.random.default_rng(SEED)`` from snapshot ``GENERATION``'s
    post-evaluation rows, in a shuffled order, each with a ``code`` (T01...)."""
    dev = load_development(run_dir, senses=None).filter(pl.col("generation") == GENERATION)
    rng = np.random.default_rng(SEED)
    parts = []
    for senses in CONDITIONS:
        rows = dev.filter(pl.col("senses") == senses).sort("replication", "rank", "trial")
        parts.append(rows[np.sort(rng.choice(rows.height, PER_CONDITION, replace=False))])
    sample = pl.concat(parts).select("phase_key", "senses", "replication", "rank", "trial",
                                     "sector", "hand_path")
    order = rng.permutation(sample.height)
    return sample[order].with_columns(
        pl.Series("code", [f"T{i + 1:02d}" for i in range(sample.height)]))


def run_again(run_dir: Path, sample: pl.DataFrame,
              generation: int = GENERATION) -> pl.DataFrame:
    """One row per trial of ``sample`` and step: the hand's x, y, z (m) and whether the hand
    has touched the ball by then (``touched``), from the genome of snapshot ``generation``
    run again."""
    run = RunDirectory.open(run_dir)
    rows = []
    for s in sample.iter_rows(named=True):
        job = stored_robot_job(run, s["phase_key"], s["senses"], s["replication"], s["rank"],
                               generation=generation, positions=(s["trial"],))
        runner = worker_trial(job.world, job.trial)
        network = network_for(decode(job.genome, as_groups(job.phase.free_groups)), job.trial)
        position = runner.world.systematic_points()[s["trial"]]
        data = runner.run(network, s["trial"] // POINTS_PER_SECTOR, position)
        n = data.steps_run
        any_face = data.contacts if data.contacts_any is None else data.contacts_any
        touch = first_touch(any_face[:n])
        hand = np.asarray(data.hand[:n])
        rows.append(pl.DataFrame({
            "code": [s["code"]] * n, "step": np.arange(n), "x": hand[:, 0], "y": hand[:, 1],
            "z": hand[:, 2], "touched": np.arange(n) >= touch if touch >= 0 else [False] * n}))
    return pl.concat(rows)


def sheets(paths: pl.DataFrame, out: Path, per_sheet: int = PER_SHEET,
           touch_line: bool = True) -> list[Path]:
    """PNG sheets of ``per_sheet`` (even) trials each: x, y, z about their means (one scale
    for all) over the 20 s, the first touch a dashed line (``touch_line``), titled by code
    only."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    codes = sorted(paths["code"].unique())
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for k in range(0, len(codes), per_sheet):
        fig, axes = plt.subplots(per_sheet // 2, 2, figsize=(12, 11 * per_sheet / 8),
                                 sharex=True, sharey=True)
        for ax, code in zip(axes.ravel(), codes[k:k + per_sheet]):
            p = paths.filter(pl.col("code") == code)
            t = p["step"].to_numpy() * 0.1
            for axis, color in zip("xyz", ("tab:red", "tab:green", "tab:blue")):
                v = p[axis].to_numpy()
                ax.plot(t, v - v.mean(), color=color, lw=1.2, label=axis)
            if touch_line and p["touched"].any():
                ax.axvline(t[int(np.argmax(p["touched"].to_numpy()))], color="k", ls="--", lw=1)
            ax.set_title(code)
            ax.set_ylim(-0.3, 0.3)
            ax.set_yticks(np.arange(-0.3, 0.31, 0.1))
            ax.grid(True, alpha=0.4)
        axes[0, 0].legend(loc="upper right", fontsize=8)
        for ax in axes[-1]:
            ax.set_xlabel("time (s)")
        for ax in axes[:, 0]:
            ax.set_ylabel("hand about its mean (m)")
        fig.tight_layout()
        path = out / f"sheet-{k // per_sheet + 1}.png"
        fig.savefig(path, dpi=80)
        plt.close(fig)
        written.append(path)
    return written


def repository_root(module: str, doc: str, argv: list[str] | None) -> Path:
    """The repository's root, the one argument of a sample's command (``module``: its name
    under ``reports``, ``doc``: its module text, whose first paragraph describes it)."""
    parser = argparse.ArgumentParser(prog=f"python -m reports.{module}",
                                     description=doc.split("\n\n")[0])
    parser.add_argument("root", type=Path, help="the repository's root")
    return parser.parse_args(argv).root


def main(argv: list[str] | None = None) -> int:
    root = repository_root("babbling_sample", __doc__, argv)
    sample = draw(root / "recordings" / FULL)
    paths = run_again(root / "recordings" / FULL, sample)
    table = paths.join(sample.select("code", "senses", "replication", "rank", "trial"),
                       on="code")
    save(root / SAMPLE, table, sheets(paths, root / PLOTS))
    return 0


def save(path: Path, table: pl.DataFrame, written: list[Path]) -> None:
    """Write a labelling sample's ``table`` to ``path``, in its run's ledger, and name the
    ``written`` sheets on stderr."""
    path.parent.mkdir(parents=True, exist_ok=True)
    integrity.write(path, lambda p: write_parquet(table, p))
    for sheet in written:
        print(sheet, file=sys.stderr)


if __name__ == "__main__":
    raise SystemExit(main())
