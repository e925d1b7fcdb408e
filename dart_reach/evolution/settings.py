"""What defines a run besides its conditions (paper sections III-C, III-D): the budgets and the
root seed (``Settings``), the trial each phase trains with (``trial_config``), the run's seed
tree, and when a phase keeps a snapshot of its best robots.

Randomness: one ``SeedSequence`` tree per run, addressed by (phase key, replication, purpose,
generation, individual) (``seed_sequence``): nothing depends on the order of evaluation or
the number of workers.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from .conditions import Phase, load_condition
from .ga import GAConfig, Scheme
from .genome import ParamGroup, as_groups, random_genome
from ..model.levers import Levers
from ..model.versions import CURRENT_MODEL_VERSION, model_version, numerics_of, variant_name
from ..model.task import TrialConfig
from ..model.world import BallConfig, SectorConfig, WorldConfig


@dataclass(frozen=True)
class Settings:
    """Budgets and seeds of a run: everything besides the conditions that defines its result:
    the model version it runs under, the world (scene, self-collision, physics step) and the
    trial's levers (``model.levers``) among them. ``world`` and ``levers`` left out are the
    version's own (``model.versions``); set away from it, the run is a named variant of its
    version (``variant``)."""

    replications: int = 10
    trials: int = 18  # trials per lifetime: 2 per sector (section III-C)
    steps: int = 200  # control steps per trial (20 s)
    seed: int = 0
    ga: GAConfig = field(default_factory=GAConfig)
    world: WorldConfig | None = None
    levers: Levers | None = None
    model_version: int = CURRENT_MODEL_VERSION

    def __post_init__(self):
        version = model_version(self.model_version)
        if self.world is None:
            object.__setattr__(self, "world", version.world())
        if self.levers is None:
            object.__setattr__(self, "levers", version.levers)
        if not isinstance(self.world, WorldConfig):
            raise ValueError(f"world must be a model.world.WorldConfig, got {self.world!r}")
        if not isinstance(self.levers, Levers):
            raise ValueError(f"levers must be a model.levers.Levers, got {self.levers!r}")
        for name in ("replications", "trials", "steps"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be a positive integer, got {getattr(self, name)}")
        if self.seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {self.seed}")

    @property
    def variant(self) -> dict[str, str]:
        """What this run changes from its model version's record (empty: the version
        itself), name -> value."""
        return model_version(self.model_version).variant(self.world, self.levers)

    def model_record(self) -> dict:
        """The manifest's ``model`` entry: the version's whole record, and the variant's name
        and changes when the run sets anything away from it."""
        changes = self.variant
        return {**model_version(self.model_version).to_json(),
                "variant": ({"name": variant_name(self.model_version, changes),
                             "changes": changes} if changes else None)}

    def to_json(self) -> dict:
        d = asdict(self)
        d["ga"]["scheme"] = self.ga.scheme.value
        d["world"]["skeleton"] = str(self.world.skeleton) if self.world.skeleton else None
        d["levers"] = self.levers.to_json()
        return d

    @classmethod
    def from_json(cls, d: dict) -> "Settings":
        """The inverse of ``to_json`` (a manifest's ``settings``). A manifest written before
        model versions and levers existed was written by model version 1 with its levers."""
        w = dict(d["world"])
        w["skeleton"] = Path(w["skeleton"]) if w.get("skeleton") else None
        w["ball"] = BallConfig(**{k: tuple(v) if isinstance(v, list) else v
                                  for k, v in w["ball"].items()})
        w["sectors"] = SectorConfig(**{k: tuple(v) if isinstance(v, list) else v
                                       for k, v in w["sectors"].items()})
        ga = dict(d["ga"], scheme=Scheme(d["ga"]["scheme"]))
        return cls(**dict(d, ga=GAConfig(**ga), world=WorldConfig(**w),
                          levers=Levers.from_json(d.get("levers")),
                          model_version=d.get("model_version", 1)))


def trial_config(phase: Phase, settings: Settings) -> TrialConfig:
    """The maturational state of a phase as the task sees it, with the run's levers and its
    model version's numerics."""
    groups = as_groups(phase.free_groups)
    levers = settings.levers
    return TrialConfig(acuity=phase.acuity, offset_sensors=phase.offset_sensors,
                       hidden_frozen=ParamGroup.HIDDEN not in groups, reflexes=phase.reflexes,
                       steps=settings.steps, trials=settings.trials,
                       reflex_inputs=levers.reflex_inputs, touch_pay=levers.touch_pay,
                       network_start=levers.network_start,
                       numerics=numerics_of(settings.model_version))


def standard_trial(phase: str = "pre", model_version: int = CURRENT_MODEL_VERSION,
                   **changes) -> TrialConfig:
    """The maturational state of a phase of the shipped ``standard`` condition (default
    pre-reaching: low acuity, internal neurons frozen, reflexes) under ``model_version``'s
    levers and numerics (default the version new runs use), with ``changes``."""
    phases = {p.name: p for p in load_condition("standard").phases}
    return replace(trial_config(phases[phase], Settings(model_version=model_version)),
                   **changes)


# ---------------------------------------------------------------- the seed tree
#: Purposes of the seed tree (the manifest's ``seeds.tree`` names the first three "init",
#: "mutate" and "evaluate"): the initial population, the mutations, the trials of a
#: lifetime, the recorded trial of a generation's best, the random genomes of the chance level.
SEED_INIT, SEED_MUTATE, SEED_LIFETIME, SEED_RECORD, SEED_BASELINE = 0, 1, 2, 3, 4


def phase_id(phase: Phase) -> int:
    """A phase's first branch in the seed tree: its key's first 8 hex digits as an integer."""
    return int(phase.key[:8], 16)


def seed_address(settings: Settings, phase: Phase, *path: int) -> tuple[int, ...]:
    """Where the run's seed for ``phase`` at ``path`` (replication, purpose, generation, ...)
    sits in its tree, as flat integers (what a ``backends.Job`` carries to a worker): the
    root seed, then the spawn key (phase key, *path)."""
    return (settings.seed, phase_id(phase), *path)


def seed_at(address: tuple[int, ...]) -> np.random.SeedSequence:
    """The seed at ``address`` (``seed_address``): the one place the tree's convention, the
    root as entropy and the rest as spawn key, is written."""
    return np.random.SeedSequence(address[0], spawn_key=tuple(address[1:]))


def seed_sequence(settings: Settings, phase: Phase, *path: int) -> np.random.SeedSequence:
    """The run's seed for ``phase`` at ``path`` (replication, purpose, generation, ...)."""
    return seed_at(seed_address(settings, phase, *path))


def baseline_genomes(settings: Settings, phase: Phase, n: int) -> np.ndarray:
    """``n`` random genomes for the chance level of ``phase`` (``evaluate --baseline``): drawn
    like an initial population, from the run's seed tree, so the first k are the same whatever
    ``n`` >= k."""
    return random_genome(np.random.default_rng(seed_sequence(settings, phase, SEED_BASELINE)),
                         n)


# ---------------------------------------------------------------- snapshots
#: Genomes per replication a snapshot keeps: the best 5, the robots the paper post-evaluates.
SNAPSHOT_ROBOTS = 5
#: Generations after which a snapshot is always kept (when snapshots are on): the first ones,
#: where the start of a phase (the motor suppression at the start of gross-reaching, Table I)
#: shows.
SNAPSHOT_EARLY = (1, 2, 5, 10)


def snapshot_due(generation: int, generations: int, every: int) -> bool:
    """Whether a phase of ``generations`` keeps a snapshot after ``generation`` (1-based)
    when snapshots are taken every ``every`` generations (0 = never)."""
    return every > 0 and (generation in SNAPSHOT_EARLY or generation % every == 0
                          or generation == generations)
