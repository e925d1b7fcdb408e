"""The figures of section IV (Figs. 5-10) from a post-evaluated run, with matplotlib.

Every figure function takes tables (the post-evaluation table of
``systematic.load_evaluation`` or ``tables.condition_trials``, the training statistics of
``generations.parquet``) and, when it draws recorded trials, the run directory; it returns a
``matplotlib.figure.Figure`` (created without pyplot, so it holds no global state: display it
in a notebook, or ``fig.savefig(path)``).

- ``training_curves`` (``training``): best and mean fitness per generation (not a paper
  figure); ``training_by_strategy``: the same per replication of a phase, marked by the
  population's strategy (``strategy_course``);
- ``fig5_performance`` (``performance``): % grasped, % reached, reaching speed, straightness
  per phase;
- ``fig6_distances_variability`` (``space``): hand-shoulder and hand-ball distance over 9
  recorded trials (one per sector) of the best pre-reacher, and movement variability (elbow,
  shoulder, trunk) per phase; beyond the paper, elbow freezing per phase;
- ``fig7_sector_maps`` (``space``): reach and grasp rate per sector and phase; beyond the
  paper, ``fig7_reach_regression``: the per-sector change of the reach rate from pre to gross;
- ``fig8_trajectories`` (``space``): recorded hand paths per phase and sensory condition;
  beyond the paper, ``fig8_babbling``: dominant frequency and power share of the hand's
  movement per phase;
- ``fig9_sensory_deprivation`` (``performance``): performance per phase and sensory condition,
  Kruskal-Wallis within each phase and the Mann-Whitney comparisons of every phase x senses
  group;
- ``table1_behaviours`` (``performance``): the behaviours Table I and section IV-A attribute
  to the phases;
- ``fig10_conditions`` (``conditions``): per-replication performance of every (condition,
  phase) of one or several runs (``tables.load_runs``) as box plots, and their pairwise
  Mann-Whitney comparisons;
- ``development_figure`` (``development``, not a paper figure): a measure over the
  generations of a condition's phases; ``strategy_figure`` (``development``): the
  pre-reaching strategies of every replication over the snapshots (``strategy_course``);
- ``budget_figure`` (``budget``, not a paper figure): each claim's effect against the
  generations per phase of runs trained at several budgets (``budgets.findings_by_budget``);
- ``forest_figure`` (``forest``, not a paper figure): every claim's effect with its
  replication-level interval against the paper's direction, one marker per budget.

The figures compute no measure and no test: the numbers they draw are the tables of
``stats`` (``performance_summary``, ``phase_statistics``, ``fig9_statistics``,
``fig10_statistics``), so that a notebook can show the numbers behind every bar, and the runs
are read by ``tables``. Bars are means over robots (a robot's value is the mean over its
trials, see ``summaries.robot_means``), error bars one standard error of that mean. Missing
data (a phase not evaluated, a measure that is NaN for every robot, a trial not recorded)
leaves an empty slot marked "n/a" rather than failing.

Needs matplotlib (the ``notebooks`` or ``dev`` extras); the rest of the package does not.
"""

from __future__ import annotations

from .budget import MOVEMENT_COLOURS, budget_figure
from .conditions import BOX_MIN, fig10_conditions
from .development import STRATEGY_PANELS, development_figure, strategy_figure
from .forest import VERDICT_COLOURS, forest_caption, forest_figure, scale_table
from .performance import (BEHAVIOUR_MEASURES, FIG5_MEASURES, fig5_performance,
                          fig9_sensory_deprivation, table1_behaviours)
from .space import (BABBLING_MEASURES, FIG6_MEASURES, FIG8_TRIAL, SECTOR_CENTRE_TRIALS, VIEWS,
                    fig6_distances_variability, fig7_reach_regression, fig7_sector_maps,
                    fig8_babbling, fig8_trajectories)
from .style import SENSES_COLOURS
from .training import TRAINING_PANELS, training_by_strategy, training_curves

__all__ = ["training_curves", "training_by_strategy", "TRAINING_PANELS", "fig5_performance",
           "fig6_distances_variability",
           "fig7_sector_maps", "fig7_reach_regression", "fig8_trajectories", "fig8_babbling",
           "fig9_sensory_deprivation", "table1_behaviours", "fig10_conditions",
           "development_figure", "strategy_figure", "STRATEGY_PANELS", "budget_figure",
           "forest_figure", "forest_caption", "scale_table", "VERDICT_COLOURS",
           "SENSES_COLOURS", "FIG5_MEASURES", "FIG6_MEASURES", "BABBLING_MEASURES",
           "BEHAVIOUR_MEASURES", "SECTOR_CENTRE_TRIALS", "FIG8_TRIAL", "VIEWS", "BOX_MIN",
           "MOVEMENT_COLOURS"]
