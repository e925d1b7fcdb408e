"""The second sample of real trials on which the babbling detector and the candidate for
claim A1 are checked by eye (docs/model/measures.md, "The second validation sample"): one
trial per condition (normal senses, ball absent) and per (generation, replication) of
``FULL``'s pre-reaching snapshots at the judged generations, drawn by
``numpy.random.default_rng(SEED)``, run again from the snapshots' genomes for their hand
paths, stored as ``SAMPLE`` and plotted under codes that name neither the run, the
generation, the replication, the robot, the condition nor any measure, and without the first
touch's line.

    python -m reports.babbling_second_sample .   # draw, run again, store, plot (~1 min)

The plots go to ``PLOTS``, the labels made from them to ``LABELS`` (by hand, before
``reports.babbling_detector`` computes anything on these trials). Nothing here computes a
detector."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl

from dart_reach.evolution.rundir import RunDirectory
from dart_reach.postevaluation.snapshots import load_development
from dart_reach.postevaluation.systematic import stored_robot_job

from . import babbling_sample as first
from .runs import FULL, JUDGED

#: The draw's seed, the conditions (one trial of each per generation and replication).
SEED = 2027
#: The seed of the codes' order: a check of the draw printed its first codes' conditions
#: before the sheets were made, so the codes were drawn again by a generator of their own.
CODE_SEED = (2027, 1)
CONDITIONS = first.CONDITIONS
SAMPLE = f"recordings/{FULL}/babbling-sample-2.parquet"
PLOTS = "docs/results/babbling-detector/sample-2"
LABELS = f"recordings/{FULL}/babbling-labels-2.csv"
#: Trials per plot sheet.
PER_SHEET = 10
#: Robots per snapshot and replication, positions per robot.
ROBOTS, POSITIONS = 5, 45


def _genome(run: RunDirectory, phase_key: str, replication: int, rank: int,
            generation: int) -> bytes:
    job = stored_robot_job(run, phase_key, "no-ball", replication, rank, generation=generation)
    return np.asarray(job.genome).tobytes()


def draw(run_dir: Path, first_sample: pl.DataFrame | None = None) -> pl.DataFrame:
    """The sample: per condition of ``CONDITIONS``, generation of ``JUDGED`` and replication
    one trial, the robot drawn uniformly among ``ROBOTS`` and the position among
    ``POSITIONS`` by ``numpy.random.default_rng(SEED)``; shuffled by
    ``default_rng(CODE_SEED)``, each with a ``code`` (U001 ...). ``first_sample`` (the first
    sample's trials: senses, replication, rank, trial at ``babbling_sample.GENERATION``) is
    excluded: a normal trial of it is drawn again, and without the ball, where a robot's
    trials are one trial, a robot whose genome is one already drawn (here or there) is
    replaced by the unit's next robot (the unit dropped when all repeat). No measure of any
    trial is read."""
    run = RunDirectory.open(run_dir)
    keys = (load_development(run_dir, senses=None)
            .filter(pl.col("generation").is_in(JUDGED))
            .select("phase_key", "generation", "replication").unique())
    phase_key = keys["phase_key"].unique().to_list()
    if len(phase_key) != 1:
        raise ValueError(f"expected one pre-reaching phase, got {phase_key}")
    phase_key = phase_key[0]
    rng = np.random.default_rng(SEED)
    old = (first_sample if first_sample is not None else
           pl.DataFrame(schema={"senses": pl.String, "replication": pl.Int64,
                                "rank": pl.Int64, "trial": pl.Int64}))
    old_normal = {(first.GENERATION, r, k, t) for r, k, t in old.filter(
        pl.col("senses") == "normal").select("replication", "rank", "trial").iter_rows()}
    seen = {_genome(run, phase_key, r, k, first.GENERATION) for r, k in old.filter(
        pl.col("senses") == "no-ball").select("replication", "rank").unique().iter_rows()}
    rows = []
    for senses in CONDITIONS:
        for generation in sorted(JUDGED):
            for replication in range(int(keys["replication"].max()) + 1):
                rank, trial = int(rng.integers(ROBOTS)), int(rng.integers(POSITIONS))
                if senses == "normal":
                    while (generation, replication, rank, trial) in old_normal:
                        rank, trial = int(rng.integers(ROBOTS)), int(rng.integers(POSITIONS))
                else:
                    for step in range(ROBOTS):
                        candidate = (rank + step) % ROBOTS
                        g = _genome(run, phase_key, replication, candidate, generation)
                        if g not in seen:
                            seen.add(g)
                            break
                    else:
                        continue
                    rank = candidate
                rows.append({"phase_key": phase_key, "senses": senses,
                             "generation": generation, "replication": replication,
                             "rank": rank, "trial": trial})
    sample = pl.DataFrame(rows)
    order = np.random.default_rng(CODE_SEED).permutation(sample.height)
    return sample[order].with_columns(
        pl.Series("code", [f"U{i + 1:03d}" for i in range(sample.height)]))


def run_again(run_dir: Path, sample: pl.DataFrame) -> pl.DataFrame:
    """One row per trial of ``sample`` and step: the hand's x, y, z (m) and whether the hand
    has touched the ball (any face) by then, each from its snapshot's genome run again."""
    parts = []
    for generation in sorted(sample["generation"].unique()):
        part = sample.filter(pl.col("generation") == generation)
        parts.append(first.run_again(run_dir, part, generation=generation))
    return pl.concat(parts)


def sheets(paths: pl.DataFrame, out: Path) -> list[Path]:
    """PNG sheets of ``PER_SHEET`` trials each: x, y, z about their means (one scale, ±0.3 m)
    over the 20 s, titled by code only, no touch marked; stored with a 32-colour palette
    (small files, the lines unchanged)."""
    from PIL import Image

    written = first.sheets(paths, out, per_sheet=PER_SHEET, touch_line=False)
    for path in written:
        with Image.open(path) as image:
            small = image.convert("RGB").quantize(colors=32)
        small.save(path, optimize=True)
    return written


def main(argv: list[str] | None = None) -> int:
    root = first.repository_root("babbling_second_sample", __doc__, argv)
    run_dir = root / "recordings" / FULL
    old = pl.read_parquet(root / first.SAMPLE).select(
        "senses", "replication", "rank", "trial").unique()
    sample = draw(run_dir, old)
    paths = run_again(run_dir, sample)
    table = paths.join(sample.select("code", "senses", "generation", "replication", "rank",
                                     "trial"), on="code")
    first.save(root / SAMPLE, table, sheets(paths, root / PLOTS))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
