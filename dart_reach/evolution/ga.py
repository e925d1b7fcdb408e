"""The learning process: a mutation-only genetic algorithm as ask/tell over immutable state (III-C).

The paper trains each robot with "an evolutionary method [47]" on a population of 20 genotypes,
each parameter encoded by 8 bits and mutated with probability 0.02 (section III-C). Two schemes
are provided (:class:`Scheme`):

``STEADY_STATE`` (default) -- the (mu + mu) scheme of Nolfi's laboratory (ref. [47]):
    each of the 20 parents makes one offspring by bit-flip mutation (every free bit flips with
    probability ``mutation_rate``); the 20 parents are re-evaluated (on new ball positions) and
    the 20 offspring evaluated; the fitness of an individual is the average of all the
    evaluations it received over its lifetime; the best 20 of the 40 survive. Ties are broken
    deterministically: a stable sort of [parents in order, offspring in order] by decreasing
    fitness, so a parent wins over an equally fit offspring.

``GENERATIONAL`` --
    the best ``n_parents`` individuals each make ``population / n_parents`` mutated offspring
    that replace the whole population; with ``elitism`` the first copy of the best individual is
    not mutated. The initial population (and any population given to :func:`init_state`) is first
    evaluated as is.

Usage (one generation)::

    candidates, state = ask(state, config, mask, rng)   # genomes to evaluate
    state = tell(state, fitness)                       # one fitness per candidate

Fitness that is NaN or infinite (e.g. a diverged simulation) counts as 0.0, the minimum of
p_multimodal (Eq. 5). States are frozen dataclasses of read-only numpy arrays and ints; they
round-trip exactly through :func:`state_to_arrays` / :func:`state_from_arrays` (for ``.npz``
checkpoints). Given the same initial state and the same ``numpy.random.Generator`` seed, the
sequence of states is identical to the last bit.
"""

from __future__ import annotations

import enum
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .genome import BITS_PER_GENE

#: The fitness given to a NaN / infinite evaluation (the minimum of p_multimodal, Eq. 5).
WORST_FITNESS = 0.0
#: Version of the array format of :func:`state_to_arrays`.
STATE_FORMAT = 1


class Scheme(enum.Enum):
    """Selection scheme of the genetic algorithm (see the module docstring)."""

    STEADY_STATE = "steady_state"
    GENERATIONAL = "generational"


class Pending(enum.Enum):
    """What the candidates handed out by :func:`ask` are, i.e. how :func:`tell` uses their
    fitness."""

    NONE = "none"  # nothing asked: tell() is an error
    STEADY_STATE = "steady_state"  # parents (re-evaluated) then one offspring per parent
    REPLACE = "replace"  # a new population that replaces the current one


@dataclass(frozen=True)
class GAConfig:
    """Parameters of the genetic algorithm (section III-C).

    ``population``: number of individuals (20). ``mutation_rate``: probability that each free bit
    flips (0.02 per bit). ``n_parents`` and ``elitism`` apply to ``Scheme.GENERATIONAL`` only;
    for that scheme ``population`` must be a multiple of ``n_parents``.
    """

    population: int = 20
    mutation_rate: float = 0.02
    scheme: Scheme = Scheme.STEADY_STATE
    n_parents: int = 4
    elitism: bool = True

    def __post_init__(self):
        if not isinstance(self.scheme, Scheme):
            raise TypeError(f"scheme must be a Scheme, got {self.scheme!r}")
        if not _is_int(self.population) or self.population < 1:
            raise ValueError(f"population must be an int >= 1, got {self.population!r}")
        if not (0.0 <= float(self.mutation_rate) <= 1.0):
            raise ValueError(f"mutation_rate must lie in [0, 1], got {self.mutation_rate!r}")
        if not _is_int(self.n_parents) or self.n_parents < 1:
            raise ValueError(f"n_parents must be an int >= 1, got {self.n_parents!r}")
        if self.scheme is Scheme.GENERATIONAL and self.population % self.n_parents:
            raise ValueError(
                f"population ({self.population}) must be a multiple of n_parents "
                f"({self.n_parents}) for the generational scheme")
        if not isinstance(self.elitism, bool):
            raise TypeError(f"elitism must be a bool, got {self.elitism!r}")


def _is_int(x) -> bool:
    return isinstance(x, (int, np.integer)) and not isinstance(x, bool)


def _frozen(a: np.ndarray, dtype) -> np.ndarray:
    a = np.array(a, dtype=dtype, copy=True)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class GAState:
    """The whole state of one run of the genetic algorithm between two calls.

    - ``genomes`` (P, L) uint8: the current population (parents), best first once evaluated.
    - ``fitness_sum`` (P,) float64 / ``fitness_count`` (P,) int64: sum and number of the
      evaluations each individual received over its lifetime (0 / 0 = not evaluated yet).
    - ``generation``: number of completed ``tell`` calls.
    - ``pending`` (C, L) uint8: the candidates handed out by the last ``ask`` and awaiting their
      fitness ((0, L) when none), ``pending_kind`` how ``tell`` will use their fitness.

    Arrays are copied and made read-only. Use :func:`states_equal` to compare two states.
    """

    genomes: np.ndarray
    fitness_sum: np.ndarray
    fitness_count: np.ndarray
    generation: int
    pending: np.ndarray
    pending_kind: Pending = Pending.NONE

    def __post_init__(self):
        g = np.asarray(self.genomes)
        if g.ndim != 2 or g.shape[0] < 1 or g.dtype != np.uint8:
            raise ValueError(f"genomes must be a non-empty (P, L) uint8 array, got "
                             f"{g.dtype} {g.shape}")
        p, length = g.shape
        object.__setattr__(self, "genomes", _frozen(g, np.uint8))
        s = _frozen(self.fitness_sum, np.float64)
        c = _frozen(self.fitness_count, np.int64)
        if s.shape != (p,) or c.shape != (p,):
            raise ValueError(f"fitness_sum and fitness_count must have shape ({p},), got "
                             f"{s.shape} and {c.shape}")
        if np.any(c < 0) or not np.all(np.isfinite(s)):
            raise ValueError("fitness_count must be >= 0 and fitness_sum finite")
        object.__setattr__(self, "fitness_sum", s)
        object.__setattr__(self, "fitness_count", c)
        pend = np.asarray(self.pending)
        if pend.ndim != 2 or pend.shape[1] != length or pend.dtype != np.uint8:
            raise ValueError(f"pending must be a (C, {length}) uint8 array, got "
                             f"{pend.dtype} {pend.shape}")
        object.__setattr__(self, "pending", _frozen(pend, np.uint8))
        if not isinstance(self.pending_kind, Pending):
            raise TypeError(f"pending_kind must be a Pending, got {self.pending_kind!r}")
        if (self.pending_kind is Pending.NONE) != (pend.shape[0] == 0):
            raise ValueError(f"pending_kind {self.pending_kind} with {pend.shape[0]} candidates")
        if self.pending_kind is Pending.STEADY_STATE and pend.shape[0] != 2 * p:
            raise ValueError(f"steady-state candidates must be 2 x {p}, got {pend.shape[0]}")
        if self.pending_kind is Pending.REPLACE and pend.shape[0] != p:
            raise ValueError(f"replacing candidates must be {p}, got {pend.shape[0]}")
        if not _is_int(self.generation) or self.generation < 0:
            raise ValueError(f"generation must be an int >= 0, got {self.generation!r}")
        object.__setattr__(self, "generation", int(self.generation))

    @property
    def population(self) -> int:
        return self.genomes.shape[0]


def init_state(genomes: np.ndarray) -> GAState:
    """The state of a new run whose (not yet evaluated) population is ``genomes`` (P, L) uint8,
    e.g. ``genome.random_genome(rng, 20)`` or :func:`transition_population`'s result."""
    genomes = np.asarray(genomes)
    if genomes.ndim != 2:
        raise ValueError(f"genomes must be a (P, L) array, got shape {genomes.shape}")
    p, length = genomes.shape
    return GAState(genomes=genomes, fitness_sum=np.zeros(p), fitness_count=np.zeros(p, np.int64),
                   generation=0, pending=np.empty((0, length), np.uint8))


def mutate(genomes: np.ndarray, free_mask: np.ndarray, rate: float,
           rng: np.random.Generator) -> np.ndarray:
    """Bit-flip mutation (III-C): every bit of every gene where ``free_mask`` is True flips
    independently with probability ``rate``. Returns a new (n, L) uint8 array.

    The random draws do not depend on ``free_mask`` (one uniform per bit of every gene), so the
    random stream is the same whatever the phase.
    """
    genomes = np.asarray(genomes)
    n, length = genomes.shape
    flips = rng.random((n, length, BITS_PER_GENE)) < rate
    xor = np.packbits(flips, axis=-1, bitorder="little").reshape(n, length)
    return genomes ^ (xor * free_mask.astype(np.uint8))


def _check_mask(free_mask: np.ndarray, length: int) -> np.ndarray:
    m = np.asarray(free_mask)
    if m.dtype != bool or m.shape != (length,):
        raise ValueError(f"free_mask must be a bool array of shape ({length},), got "
                         f"{m.dtype} {m.shape}")
    return m


def lifetime_fitness(state: GAState) -> np.ndarray:
    """Each individual's average fitness over its lifetime (sum / count); NaN if never
    evaluated."""
    out = np.full(state.population, np.nan)
    np.divide(state.fitness_sum, state.fitness_count, out=out, where=state.fitness_count > 0)
    return out


def _ranking(avg: np.ndarray) -> np.ndarray:
    """Indices by decreasing fitness; ties keep the original order (stable)."""
    return np.argsort(-avg, kind="stable")


def ask(state: GAState, config: GAConfig, free_mask: np.ndarray,
        rng: np.random.Generator) -> tuple[np.ndarray, GAState]:
    """The genomes to evaluate this generation, and the state awaiting their fitness.

    Steady-state: the P parents followed by their P offspring (offspring i from parent i).
    Generational: the P offspring of the best ``n_parents`` (or, if the population has never been
    evaluated, the population itself). Only genes where ``free_mask`` is True mutate.
    Raises ``ValueError`` if the previous candidates have not been told yet.
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    if state.pending_kind is not Pending.NONE:
        raise ValueError("ask() called twice: tell() the fitness of the pending candidates first")
    if state.population != config.population:
        raise ValueError(f"the state holds {state.population} individuals but the config "
                         f"expects a population of {config.population}")
    mask = _check_mask(free_mask, state.genomes.shape[1])
    parents = state.genomes
    if config.scheme is Scheme.STEADY_STATE:
        offspring = mutate(parents, mask, config.mutation_rate, rng)
        candidates = np.concatenate([parents, offspring])
        kind = Pending.STEADY_STATE
    elif np.any(state.fitness_count == 0):
        candidates, kind = parents.copy(), Pending.REPLACE
    else:
        best = _ranking(lifetime_fitness(state))[: config.n_parents]
        copies = np.repeat(parents[best], config.population // config.n_parents, axis=0)
        candidates = mutate(copies, mask, config.mutation_rate, rng)
        if config.elitism:
            candidates[0] = parents[best[0]]
        kind = Pending.REPLACE
    new = GAState(genomes=state.genomes, fitness_sum=state.fitness_sum,
                  fitness_count=state.fitness_count, generation=state.generation,
                  pending=candidates, pending_kind=kind)
    return new.pending, new


def sanitize_fitness(fitness: Sequence[float] | np.ndarray) -> np.ndarray:
    """Float64 copy of ``fitness`` with NaN and +-inf replaced by :data:`WORST_FITNESS` (0.0)."""
    f = np.array(fitness, dtype=np.float64, copy=True).reshape(-1)
    f[~np.isfinite(f)] = WORST_FITNESS
    return f


def tell(state: GAState, fitness: Sequence[float] | np.ndarray) -> GAState:
    """The next state, given one fitness per candidate of the last :func:`ask` (same order).

    Steady-state: the parents' sums and counts accumulate their new evaluation, the offspring
    start with one; the best P of the 2P by lifetime average survive (stable: parents first on
    ties), sorted best first. Replace: the candidates become the population with one evaluation
    each, sorted best first (stable). The generation counter is incremented.
    """
    if state.pending_kind is Pending.NONE:
        raise ValueError("tell() called without a pending ask()")
    f = np.asarray(fitness)
    if f.shape != (state.pending.shape[0],):
        raise ValueError(f"expected {state.pending.shape[0]} fitness values (one per candidate), "
                         f"got shape {f.shape}")
    f = sanitize_fitness(f)
    p = state.population
    if state.pending_kind is Pending.STEADY_STATE:
        sums = np.concatenate([state.fitness_sum + f[:p], f[p:]])
        counts = np.concatenate([state.fitness_count + 1, np.ones(p, np.int64)])
    else:
        sums, counts = f, np.ones(p, np.int64)
    order = _ranking(sums / counts)[:p]
    return GAState(genomes=state.pending[order], fitness_sum=sums[order],
                   fitness_count=counts[order], generation=state.generation + 1,
                   pending=np.empty((0, state.pending.shape[1]), np.uint8))


def best_k(state: GAState, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``k`` best individuals by lifetime average fitness: genomes (k, L) and fitness (k,),
    best first (stable on ties). Raises ``ValueError`` if the population was never evaluated."""
    if np.any(state.fitness_count == 0):
        raise ValueError("the population has not been evaluated yet (no tell() since init_state)")
    if not _is_int(k) or not 1 <= k <= state.population:
        raise ValueError(f"k must be an int in [1, {state.population}], got {k!r}")
    avg = lifetime_fitness(state)
    order = _ranking(avg)[:k]
    return state.genomes[order].copy(), avg[order]


def best(state: GAState) -> tuple[np.ndarray, float]:
    """The best individual's genome (L,) and its lifetime average fitness."""
    genomes, fitness = best_k(state, 1)
    return genomes[0], float(fitness[0])


def generation_stats(fitness: Sequence[float] | np.ndarray) -> dict[str, float]:
    """``{"best", "mean", "min"}`` of one generation's fitness (NaN/inf counted as 0.0)."""
    f = sanitize_fitness(fitness)
    if f.size == 0:
        raise ValueError("generation_stats() needs at least one fitness value")
    return {"best": float(f.max()), "mean": float(f.mean()), "min": float(f.min())}


def transition_population(best_per_replication: Sequence[np.ndarray], n: int = 2,
                          population: int = 20) -> np.ndarray:
    """The initial population of the next phase (III-D): the best ``n`` genomes of each
    replication of the previous phase, merged (replication order, best first within each).

    ``best_per_replication[r]`` is an (k, L) array of replication r's genomes sorted best first
    (e.g. ``best_k(final_state, n)[0]``); its first ``n`` rows are taken. Raises ``ValueError``
    if a replication has fewer than ``n`` genomes, the lengths differ, or the merged count is not
    ``population`` (10 replications x 2 = 20 in the paper).
    """
    if not _is_int(n) or n < 1:
        raise ValueError(f"n must be an int >= 1, got {n!r}")
    parts = []
    for r, g in enumerate(best_per_replication):
        g = np.asarray(g)
        if g.ndim != 2 or g.dtype != np.uint8:
            raise ValueError(f"replication {r}: expected a (k, L) uint8 array, got "
                             f"{g.dtype} {g.shape}")
        if g.shape[0] < n:
            raise ValueError(f"replication {r}: {g.shape[0]} genomes, fewer than n={n}")
        parts.append(g[:n])
    if len({p.shape[1] for p in parts}) > 1:
        raise ValueError(f"genome lengths differ across replications: "
                         f"{sorted({p.shape[1] for p in parts})}")
    total = n * len(parts)
    if total != population:
        raise ValueError(f"{len(parts)} replications x {n} genomes = {total} individuals, but the "
                         f"population size is {population}")
    return np.concatenate(parts)


_ARRAY_KEYS = ("format", "genomes", "fitness_sum", "fitness_count", "generation", "pending",
               "pending_kind")


def state_to_arrays(state: GAState) -> dict[str, np.ndarray]:
    """The state as a dict of numpy arrays (no objects: ``np.savez`` / ``np.load`` with the
    default ``allow_pickle=False`` round-trip it exactly)."""
    return {
        "format": np.array(STATE_FORMAT, np.int64),
        "genomes": np.array(state.genomes),
        "fitness_sum": np.array(state.fitness_sum),
        "fitness_count": np.array(state.fitness_count),
        "generation": np.array(state.generation, np.int64),
        "pending": np.array(state.pending),
        "pending_kind": np.array(state.pending_kind.value),
    }


def state_from_arrays(d) -> GAState:
    """Inverse of :func:`state_to_arrays` (accepts a dict or an ``np.load`` result)."""
    missing = [k for k in _ARRAY_KEYS if k not in d]
    if missing:
        raise ValueError(f"not a GA state: missing arrays {missing}")
    if int(d["format"]) != STATE_FORMAT:
        raise ValueError(f"unsupported GA state format {int(d['format'])} "
                         f"(this version reads {STATE_FORMAT})")
    try:
        kind = Pending(str(d["pending_kind"]))
    except ValueError:
        raise ValueError(f"unknown pending_kind {str(d['pending_kind'])!r}") from None
    return GAState(genomes=d["genomes"], fitness_sum=d["fitness_sum"],
                   fitness_count=d["fitness_count"], generation=int(d["generation"]),
                   pending=d["pending"], pending_kind=kind)


def states_equal(a: GAState, b: GAState) -> bool:
    """True if two states are identical to the last bit."""
    da, db = state_to_arrays(a), state_to_arrays(b)
    return all(da[k].dtype == db[k].dtype and da[k].shape == db[k].shape
               and da[k].tobytes() == db[k].tobytes() for k in _ARRAY_KEYS)


__all__ = [
    "GAConfig", "GAState", "Pending", "Scheme", "WORST_FITNESS", "ask", "best", "best_k",
    "generation_stats", "init_state", "lifetime_fitness", "mutate", "sanitize_fitness",
    "state_from_arrays", "state_to_arrays", "states_equal", "tell", "transition_population",
]
