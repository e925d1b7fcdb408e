"""What the calibration of the verdict rules shares (``calibration``, ``paired_calibration``):
the nesting of a simulated run (replications x robots), how many data sets a row is over, the
Monte-Carlo tolerance a bounded row must meet, and a row of the table. Section IV's claims are
judged with the replication as the unit (DESIGN.md, "Findings as data")."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: Data sets per rule, nesting and scenario; the Monte-Carlo standard error of a rate near
#: ALPHA is then sqrt(0.05 x 0.95 / 2000) = 0.0049.
DATASETS = 2000
#: The outlying replication of the robustness null, in between-replication s.d.
OUTLIER = 4.0
#: One-sided z of the Monte-Carlo tolerance (99 %): a rule fails when its rate exceeds
#: ALPHA + Z_MC x its standard error, or its coverage falls below the level - Z_MC x s.e.
Z_MC = 2.33


@dataclass(frozen=True)
class Nesting:
    """Replications per group, robots per replication, and the s.d. of replication effects
    and of robots within a replication, in the measure's units."""

    replications: int
    robots: int = 5
    between_sd: float = 1.0
    within_sd: float = 0.2

    @property
    def label(self) -> str:
        return (f"{self.replications} x {self.robots} (s.d. {self.between_sd:g} between, "
                f"{self.within_sd:g} within)")

    @property
    def mean_sd(self) -> float:
        """s.d. of a replication's mean over its robots."""
        return math.sqrt(self.between_sd ** 2 + self.within_sd ** 2 / self.robots)


#: The runs' ratio of within- to between-replication s.d. (``spreads``, over phases and
#: measures; docs/results/replication.md): the lowest lower quartile (0.62) and the highest
#: upper quartile (2.97) over the project's committed replication runs, rounded.
RUN_RATIOS = (0.6, 3.0)
#: The nestings of the runs: 4 replications (the 10- and 50-generation runs), 10 (the
#: paper's), each at the two ends of the runs' quartile ratios.
NESTINGS = tuple(Nesting(r, 5, 1.0, w) for r in (4, 10) for w in RUN_RATIOS)


def robots(rng: np.random.Generator, nest: Nesting, shift: float = 0.0) -> np.ndarray:
    """One group's robot values, shape (replications, robots): replication effects
    N(shift, between_sd), robots N(replication, within_sd)."""
    rep = rng.normal(shift, nest.between_sd, nest.replications)
    return rep[:, None] + rng.normal(0.0, nest.within_sd, (nest.replications, nest.robots))



def rate(flags) -> float:
    """The share of true ``flags`` (a rate in [0, 1])."""
    return float(np.mean(flags))


def row(rule: str, nest: Nesting, scenario: str, measure: str, value: float, bound: float,
        kind: str, datasets: int = DATASETS) -> dict:
    """``kind``: "at most" (an error rate against ``bound``), "at least" (a coverage),
    "power" or "reported" (a rule not used, for comparison; neither has a bound); ``value``
    over ``datasets`` data sets (the Monte-Carlo error of the check)."""
    if kind not in ("at most", "at least", "power", "reported"):
        raise ValueError(f"unknown kind {kind!r}")
    free = kind in ("power", "reported")
    se = math.sqrt(max(bound * (1 - bound), 1e-12) / datasets) if not free else math.nan
    ok = (value <= bound + Z_MC * se if kind == "at most" else
          value >= bound - Z_MC * se if kind == "at least" else None)
    return {"rule": rule, "replications": nest.replications, "robots": nest.robots,
            "between_sd": nest.between_sd, "within_sd": nest.within_sd, "scenario": scenario,
            "measure": measure, "value": value, "bound": bound if not free else math.nan,
            "kind": kind, "ok": ok}


def repeat(rng, n, draw: Callable):
    """``n`` draws of ``draw(rng)``, in order (one stream: a block's rows are a function of
    its seed)."""
    return [draw(rng) for _ in range(n)]

