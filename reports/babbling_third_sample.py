"""The third sample of real trials on which the babbling measures are checked by eye
(docs/model/measures.md, "The third validation sample"): trials that no measure had been
computed on when it was drawn, the campaign's committed pre-reaching snapshots (``RUN``, not
yet post-evaluated then), under normal senses, with the ball absent and without sight, drawn
by ``numpy.random.default_rng(SEED)``, run again from the snapshots' genomes for their hand
paths, stored as ``SAMPLE`` (no measure) and plotted under codes that name neither the
generation, the replication, the robot, the condition nor any measure, without the first
touch's line.

    python -m reports.babbling_third_sample .   # draw, run again, store, plot (~1 min)

The labels made from the plots go to ``LABELS``, by hand, before anything computes a measure
on these trials (``reports.babbling_validation``). Nothing here computes one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import polars as pl

from dart_reach.evolution.rundir import RunDirectory

from . import babbling_sample as first
from . import babbling_second_sample as second

#: The run drawn from (its committed compact state) and the snapshots' generations: every
#: snapshot committed when the protocol was written.
RUN = "campaign/standard-v3"
GENERATIONS = (1, 2, 5, 10, 20, 30)
#: The draw's seed, the codes' order's, the conditions and the trials per condition.
SEED, CODE_SEED = 2028, (2028, 1)
CONDITIONS = ("normal", "no-ball", "no-sight")
PER_CONDITION = 40
SAMPLE = "recordings/babbling-validation/sample-3.parquet"
LABELS = "recordings/babbling-validation/labels-3.csv"
PLOTS = "docs/results/babbling-detector/sample-3"


def draw(run_dir: Path) -> pl.DataFrame:
    """The sample: per condition of ``CONDITIONS``, ``PER_CONDITION`` of the (generation,
    replication) units of ``GENERATIONS`` drawn without replacement, then in each (in
    generation, replication order) the robot uniformly among the snapshot's and the position
    among the 45, all by ``numpy.random.default_rng(SEED)``; without the ball a draw whose
    genome repeats one already drawn without the ball is replaced by the unit's next robot
    (the unit dropped when all repeat). Shuffled by ``default_rng(CODE_SEED)``, each with a
    ``code`` (W001 ...). No measure of any trial is read (none exists)."""
    run = RunDirectory.open(run_dir)
    phase = next(p for c, p in run.unique_phases() if p.notation == "pre")
    genomes = {gen: g for gen, g, _ in run.snapshots(phase) if gen in GENERATIONS}
    if sorted(genomes) != list(GENERATIONS):
        raise ValueError(f"{run_dir}: snapshots {sorted(genomes)}, expected {GENERATIONS}")
    replications, robots = genomes[GENERATIONS[0]].shape[:2]
    units = [(g, r) for g in GENERATIONS for r in range(replications)]
    rng = np.random.default_rng(SEED)
    seen, rows = set(), []
    for senses in CONDITIONS:
        for i in np.sort(rng.choice(len(units), PER_CONDITION, replace=False)):
            generation, replication = units[i]
            rank, trial = int(rng.integers(robots)), int(rng.integers(second.POSITIONS))
            if senses == "no-ball":
                ranks = [(rank + step) % robots for step in range(robots)]
                rank = next((k for k in ranks
                             if genomes[generation][replication, k].tobytes() not in seen), None)
                if rank is None:
                    continue
                seen.add(genomes[generation][replication, rank].tobytes())
            rows.append({"phase_key": phase.key, "senses": senses, "generation": generation,
                         "replication": replication, "rank": rank, "trial": trial})
    sample = pl.DataFrame(rows)
    order = np.random.default_rng(CODE_SEED).permutation(sample.height)
    return sample[order].with_columns(
        pl.Series("code", [f"W{i + 1:03d}" for i in range(sample.height)]))


def main(argv: list[str] | None = None) -> int:
    root = first.repository_root("babbling_third_sample", __doc__, argv)
    run_dir = root / "recordings" / RUN
    sample = draw(run_dir)
    paths = second.run_again(run_dir, sample)
    table = paths.join(sample.drop("phase_key"), on="code")
    first.save(root / SAMPLE, table, second.sheets(paths, root / PLOTS))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
