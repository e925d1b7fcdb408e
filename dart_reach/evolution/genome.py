"""The genotype: every parameter of the controller encoded by 8 bits (paper section III-C).

A genome is a 1-D ``numpy.uint8`` array of ``N_GENES`` *codes*, one code (0..255, i.e. the 8
bits of one parameter) per parameter of :class:`~dart_reach.ctrnn.NetworkParams`. Mutation flips
the individual bits of the codes (:func:`dart_reach.evolution.mutate`); decoding is linear::

    value = lo + (hi - lo) * code / 255

so code 0 gives ``lo``, code 255 gives ``hi`` and the grid step is ``(hi - lo) / 255``.

A genome always holds the FULL parameter vector, whatever the phase, so that a genome carries
over from one developmental phase to the next (section III-D). What changes between phases is
which *parameter groups* are free (:class:`ParamGroup`): the genes of a free group decode from
their codes and may mutate; the genes of a frozen group are carried along untouched and decode to
the group's fixed value, whatever their bits.

Ranges (the paper gives none; these are the defaults of the Evorobot/FARSA tools of Nolfi's
laboratory, where the experiment was run):

- connection weights and biases (thresholds): [-5, 5]
- time constants tau: [0, 1] (section III-B: 0 <= tau <= 1)
- gains (internal neurons, sight-offset sensors): [0, 1]

Fixed values of frozen groups: weights 0 and biases 0 (section III-D: the connections to and from
the internal neurons are "frozen ... to a null value"), time constants 0, gains 1.0 (section
III-B: the gain of the other neurons "is manually set to 1.0").

Layout: the fields of ``NetworkParams`` in declaration order, each flattened in C order
(weights are [post, pre]); see :data:`LAYOUT` and :func:`field_slice`.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..model.ctrnn import N_HIDDEN, N_MOTORS, N_SENSORS, NetworkParams

#: Bits per parameter (section III-C).
BITS_PER_GENE = 8
#: Largest code of a gene.
CODE_MAX = 2**BITS_PER_GENE - 1

WEIGHT_RANGE = (-5.0, 5.0)
BIAS_RANGE = (-5.0, 5.0)
TAU_RANGE = (0.0, 1.0)
GAIN_RANGE = (0.0, 1.0)


class ParamGroup(enum.Enum):
    """Groups of parameters that a developmental phase frees or freezes together (III-D).

    - ``DIRECT``: sensory-to-motor weights, motor biases and motor time constants (free in every
      phase of the paper; the only free group during pre-reaching).
    - ``HIDDEN``: weights to and from the internal neurons, their biases and time constants
      (freed at gross-reaching).
    - ``HIDDEN_GAIN``: the gains of the internal neurons (freed at fine-reaching).
    - ``OFFSET_GAIN``: the gains of the two sight-offset sensors (freed at fine-reaching, with the
      offset sensors themselves).

    The value is the name used in condition files (``free_groups = ["direct", "hidden"]``).
    """

    DIRECT = "direct"
    HIDDEN = "hidden"
    HIDDEN_GAIN = "hidden_gain"
    OFFSET_GAIN = "offset_gain"


ALL_GROUPS: frozenset[ParamGroup] = frozenset(ParamGroup)


@dataclass(frozen=True)
class GeneField:
    """One field of ``NetworkParams`` inside the genome: genes ``start:stop`` hold its codes.

    ``lo``/``hi`` are the decoding range, ``fixed`` the value the field takes while its group is
    frozen.
    """

    name: str
    shape: tuple[int, ...]
    group: ParamGroup
    lo: float
    hi: float
    fixed: float
    start: int
    stop: int

    @property
    def size(self) -> int:
        return self.stop - self.start

    @property
    def slice(self) -> slice:
        return slice(self.start, self.stop)

    @property
    def step(self) -> float:
        """Decoding resolution: the value between two successive codes."""
        return (self.hi - self.lo) / CODE_MAX


def _build_layout() -> tuple[GeneField, ...]:
    spec = (
        # name, shape, group, range, fixed value
        ("w_sensor_motor", (N_MOTORS, N_SENSORS), ParamGroup.DIRECT, WEIGHT_RANGE, 0.0),
        ("w_sensor_hidden", (N_HIDDEN, N_SENSORS), ParamGroup.HIDDEN, WEIGHT_RANGE, 0.0),
        ("w_hidden_motor", (N_MOTORS, N_HIDDEN), ParamGroup.HIDDEN, WEIGHT_RANGE, 0.0),
        ("bias_hidden", (N_HIDDEN,), ParamGroup.HIDDEN, BIAS_RANGE, 0.0),
        ("bias_motor", (N_MOTORS,), ParamGroup.DIRECT, BIAS_RANGE, 0.0),
        ("tau_hidden", (N_HIDDEN,), ParamGroup.HIDDEN, TAU_RANGE, 0.0),
        ("tau_motor", (N_MOTORS,), ParamGroup.DIRECT, TAU_RANGE, 0.0),
        ("gain_hidden", (N_HIDDEN,), ParamGroup.HIDDEN_GAIN, GAIN_RANGE, 1.0),
        ("gain_offset", (2,), ParamGroup.OFFSET_GAIN, GAIN_RANGE, 1.0),
    )
    declared = tuple(NetworkParams.__dataclass_fields__)
    if tuple(s[0] for s in spec) != declared:
        raise RuntimeError(
            f"genome layout {tuple(s[0] for s in spec)} does not match NetworkParams {declared}")
    fields, start = [], 0
    for name, shape, group, (lo, hi), fixed in spec:
        size = int(np.prod(shape))
        fields.append(GeneField(name, shape, group, lo, hi, fixed, start, start + size))
        start += size
    return tuple(fields)


#: The fields of the genome, in order.
LAYOUT: tuple[GeneField, ...] = _build_layout()
#: Number of genes (= parameters) of a genome: 716.
N_GENES: int = LAYOUT[-1].stop
_BY_NAME = {f.name: f for f in LAYOUT}


def n_genes() -> int:
    """Number of genes of a genome (one 8-bit code per controller parameter)."""
    return N_GENES


def field(name: str) -> GeneField:
    """The layout entry of the ``NetworkParams`` field ``name``."""
    try:
        return _BY_NAME[name]
    except KeyError:
        raise ValueError(f"unknown parameter field {name!r}; known: {sorted(_BY_NAME)}") from None


def field_slice(name: str) -> slice:
    """The genes of the ``NetworkParams`` field ``name`` (flattened in C order)."""
    return field(name).slice


def as_groups(groups: Iterable[ParamGroup | str]) -> frozenset[ParamGroup]:
    """Normalise an iterable of groups or group names ("direct", ...) to a frozenset."""
    if isinstance(groups, (str, ParamGroup)):
        groups = (groups,)
    out = set()
    for g in groups:
        if isinstance(g, ParamGroup):
            out.add(g)
        elif isinstance(g, str):
            try:
                out.add(ParamGroup(g))
            except ValueError:
                known = [m.value for m in ParamGroup]
                raise ValueError(f"unknown parameter group {g!r}; known: {known}") from None
        else:
            raise TypeError(f"expected a ParamGroup or its name, got {type(g).__name__}: {g!r}")
    return frozenset(out)


def check_genome(genome: np.ndarray) -> np.ndarray:
    """Return ``genome`` as an array after checking it is a uint8 vector of ``N_GENES`` codes."""
    genome = np.asarray(genome)
    if genome.dtype != np.uint8:
        raise TypeError(f"a genome is an array of uint8 codes, got dtype {genome.dtype}")
    if genome.shape != (N_GENES,):
        raise ValueError(f"a genome has shape ({N_GENES},), got {genome.shape}")
    return genome


def decode_codes(codes: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Linear decoding of 8-bit codes: ``lo + (hi - lo) * code / 255`` (float64)."""
    return lo + (hi - lo) * np.asarray(codes, dtype=np.float64) / CODE_MAX


def encode_values(values: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The code (uint8) nearest to each value; values must lie within ``[lo, hi]``.

    Exact inverse of :func:`decode_codes` on its grid. Ties (a value exactly halfway between two
    codes, e.g. 0 in [-5, 5]) round to the even code (``numpy.rint``).
    """
    values = np.asarray(values, dtype=np.float64)
    if not np.all(np.isfinite(values)):
        raise ValueError("cannot encode non-finite values")
    tol = 1e-9 * (hi - lo)
    if np.any(values < lo - tol) or np.any(values > hi + tol):
        raise ValueError(
            f"values outside the range [{lo}, {hi}]: min {values.min()}, max {values.max()}")
    codes = np.rint((values - lo) / (hi - lo) * CODE_MAX)
    return np.clip(codes, 0, CODE_MAX).astype(np.uint8)


def decode(genome: np.ndarray, free_groups: Iterable[ParamGroup | str]) -> NetworkParams:
    """The controller parameters encoded by ``genome`` when ``free_groups`` are free (III-C/D).

    Fields of free groups decode linearly from their codes; fields of frozen groups take their
    fixed value (0 for weights, biases and time constants, 1.0 for gains) whatever their bits.
    """
    genome = check_genome(genome)
    free = as_groups(free_groups)
    values = {}
    for f in LAYOUT:
        if f.group in free:
            v = decode_codes(genome[f.slice], f.lo, f.hi).reshape(f.shape)
        else:
            v = np.full(f.shape, f.fixed, dtype=np.float64)
        values[f.name] = v
    return NetworkParams(**values)


def encode(params: NetworkParams) -> np.ndarray:
    """The genome whose codes are nearest to every value of ``params`` (all groups free).

    ``decode(encode(p), ALL_GROUPS) == p`` exactly when every value of ``p`` lies on the 8-bit
    grid of its range. Raises ``ValueError`` for a value outside its range or a wrong shape.
    """
    genome = np.empty(N_GENES, dtype=np.uint8)
    for f in LAYOUT:
        v = np.asarray(getattr(params, f.name), dtype=np.float64)
        if v.shape != f.shape:
            raise ValueError(f"{f.name}: expected shape {f.shape}, got {v.shape}")
        try:
            genome[f.slice] = encode_values(v.ravel(), f.lo, f.hi)
        except ValueError as e:
            raise ValueError(f"{f.name}: {e}") from None
    return genome


def free_mask(free_groups: Iterable[ParamGroup | str]) -> np.ndarray:
    """Boolean vector (``N_GENES``,): True for the genes that may mutate (those of free groups)."""
    free = as_groups(free_groups)
    mask = np.zeros(N_GENES, dtype=bool)
    for f in LAYOUT:
        if f.group in free:
            mask[f.slice] = True
    return mask


def released_codes() -> np.ndarray:
    """For every gene, the code nearest to its field's fixed value (what :func:`release` sets).

    Weights and biases: code 128, i.e. +5/255 ~ +0.0196 (0 lies halfway between codes 127 and 128
    and rounds to the even one); time constants: code 0 (exactly 0); gains: code 255 (exactly 1).
    """
    codes = np.empty(N_GENES, dtype=np.uint8)
    for f in LAYOUT:
        codes[f.slice] = encode_values(f.fixed, f.lo, f.hi)
    return codes


def release(genome: np.ndarray, newly_free_groups: Iterable[ParamGroup | str]) -> np.ndarray:
    """A copy of ``genome`` whose genes of ``newly_free_groups`` encode (nearly) their fixed value.

    Applied at a phase transition (III-D) to the groups the new phase frees, so that the freshly
    freed parameters start from the value they had while frozen rather than from the random bits
    they carried: the internal neurons' weights and biases start at +5/255 ~ 0.0196 (the 8-bit
    grid of [-5, 5] has no 0; residual at most 5/255 in absolute value), their time constants at 0
    and the gains at exactly 1.0. Works on one genome (``N_GENES``,) or a population
    (n, ``N_GENES``).
    """
    genome = np.asarray(genome)
    if genome.dtype != np.uint8 or genome.shape[-1:] != (N_GENES,) or genome.ndim > 2:
        raise ValueError(
            f"expected uint8 genomes of shape ({N_GENES},) or (n, {N_GENES}), "
            f"got {genome.dtype} {genome.shape}")
    mask = free_mask(newly_free_groups)
    out = genome.copy()
    out[..., mask] = released_codes()[mask]
    return out


def random_genome(rng: np.random.Generator, n: int | None = None) -> np.ndarray:
    """Uniformly random codes (every bit 0 or 1 with probability 1/2), as in III-C's initial
    population. Shape (``N_GENES``,) if ``n`` is None, else (n, ``N_GENES``)."""
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    shape = (N_GENES,) if n is None else (int(n), N_GENES)
    if n is not None and n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    return rng.integers(0, CODE_MAX + 1, size=shape, dtype=np.uint8)
