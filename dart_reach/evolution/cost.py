"""What a training run costs, known before it starts (``dart-reach train`` announces it for a
long run): generations to train and core-hours, from the benchmarked cost of one generation."""

from __future__ import annotations

from dataclasses import dataclass

from .conditions import Condition
from .ga import Scheme
from .settings import Settings

#: Core-seconds of one replication-generation at the paper's budget (20 genotypes, steady
#: state: 40 lifetimes of 18 trials of 200 control steps, the shipped evolved robots):
#: ``generation_core_s`` of ``dart-reach bench``, low and high of five quiet runs on the
#: project's 2-core reference machine on 2026-11-24 (docs/results/benchmarks.md; the host's speed
#: varies by about a third from day to day).
GENERATION_CORE_S = (43.0, 44.7)


@dataclass(frozen=True)
class CostEstimate:
    """The size of a training run: ``replication_generations`` (generations of every phase
    trained, a phase shared by conditions once, times replications) and ``core_hours`` (low,
    high), from ``GENERATION_CORE_S`` scaled by lifetimes, trials and steps."""

    replication_generations: int
    core_hours: tuple[float, float]


def cost_estimate(conditions: list[Condition], settings: Settings) -> CostEstimate:
    """How much training ``conditions`` under ``settings`` costs (see ``CostEstimate``): the
    cost of a generation is taken proportional to lifetimes x trials x steps, and evolved
    robots (which touch the ball) cost more than the random networks a run starts from, so
    it is an upper-side estimate for short runs."""
    phases = {p.key: p for c in conditions for p in c.phases}
    rep_gens = sum(p.generations for p in phases.values()) * settings.replications
    lifetimes = settings.ga.population * (2 if settings.ga.scheme is Scheme.STEADY_STATE
                                          else 1)
    scale = lifetimes / 40 * settings.trials / 18 * settings.steps / 200
    return CostEstimate(rep_gens, tuple(rep_gens * scale * s / 3600 for s in GENERATION_CORE_S))
