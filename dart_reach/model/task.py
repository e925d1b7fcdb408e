"""One trial and one lifetime of the reach-and-grasp task (paper sections III-B, III-C).

A trial: the robot is reset to its home posture, the ball placed at rest in a sector, and the
network drives the robot for 200 steps of 0.1 s (20 s). At each step the sensors are read, the
fitness terms computed (p_sight, p_touch, p_multimodal = min of the two, Eq. 5), the network
updated and its 14 motor outputs sent to the world as targets.

A lifetime, what evolution scores an individual by (section III-C), is 18 trials, 2 per sector
at random points, and its fitness the mean of p_multimodal over all their steps (a diverged trial
counts 0). Under the steady-state GA a parent lives again in every generation it survives, at
new positions, and its lifetime fitness is the mean over its lifetimes (``evolution.ga``).

Everything the later analysis needs is kept per step in numpy arrays (``TrialData``).
A trial whose network or physics becomes NaN or infinite stops there with fitness 0 and
``diverged = True``.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np

from ..pinning import require_pinned_kernels
from .ctrnn import N_HIDDEN, N_MOTORS, N_SENSORS, Network, NetworkParams
from .icub import HAND_SEGMENTS
from .levers import NetworkStart, ReflexInputs, TouchPay, coerce_levers
from .steps import TrialSteps
from .versions import Numerics
from .world import N_SECTORS, World

N_SEGMENTS = len(HAND_SEGMENTS)


class Senses(enum.Enum):
    """Conditions of the post-evaluation. The sensory conditions of section IV-B (Fig. 9): the
    deprived inputs are clamped to the value that means "nothing sensed". ``NO_BALL``, the
    ball-absent test of section IV-A-1 (Fig. 8): the ball is taken out of the scene (parked at
    ``world.BALL_PARKED``, out of reach and out of view) and the touch, sight and offset inputs
    read "nothing sensed"; the trial's ``ball`` record holds where the ball would hang."""

    NORMAL = "normal"
    NO_TOUCH = "no-touch"
    NO_SIGHT = "no-sight"
    NOTHING = "nothing"
    NO_BALL = "no-ball"


_NO_TOUCH = (Senses.NO_TOUCH, Senses.NOTHING, Senses.NO_BALL)
_NO_SIGHT = (Senses.NO_SIGHT, Senses.NOTHING, Senses.NO_BALL)


@dataclass(frozen=True)
class TrialConfig:
    """Everything the paper manipulates about the robot's nervous system, as data.

    ``acuity`` is the exponent a of Eqs. 1-2: 3 in pre-reaching (low acuity), 1 afterwards, as
    the paper's text (section III-B) says; its Table I swaps the two values.
    ``reflex_inputs``, ``touch_pay`` and ``network_start`` are the trial's levers
    (``levers.Levers``; the defaults are model version 1's); ``numerics`` how the model
    version computes them (``versions.Numerics``; version 1's by default).
    """

    acuity: float = 1.0
    offset_sensors: bool = False  # fine-reaching (section III-D, 3)
    hidden_frozen: bool = False  # internal neurons held at 0 (pre-reaching, Fig. 3)
    reflexes: bool = True  # orienting and grasp reflexes (section III-D, 1)
    senses: Senses = Senses.NORMAL
    steps: int = 200  # 20 s of 0.1 s steps (section III-C)
    trials: int = 18  # trials per lifetime: 2 per sector (section III-C)
    reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET
    touch_pay: TouchPay = TouchPay.FACES
    network_start: NetworkStart = NetworkStart.HOLD_HOME
    numerics: Numerics = Numerics.REFERENCE

    def __post_init__(self):
        coerce_levers(self)
        if not isinstance(self.numerics, Numerics):
            object.__setattr__(self, "numerics", Numerics(self.numerics))
        if not (self.acuity > 0 and math.isfinite(self.acuity)):
            raise ValueError(f"acuity must be a positive number, got {self.acuity!r}")
        if self.steps <= 0 or self.trials <= 0:
            raise ValueError("steps and trials must be positive")
        if not isinstance(self.senses, Senses):
            object.__setattr__(self, "senses", Senses(self.senses))

    @property
    def touch_deprived(self) -> bool:
        """Whether the touch sensors read ``sensors.NO_TOUCH`` whatever touches (section IV-B)."""
        return self.senses in _NO_TOUCH

    @property
    def sight_deprived(self) -> bool:
        """Whether the sight and offset sensors read ``sensors.NO_SIGHT`` (section IV-B)."""
        return self.senses in _NO_SIGHT

    @property
    def offsets_sensed(self) -> bool:
        """Whether the offset sensors (Eq. 4) read the hand and the ball."""
        return self.offset_sensors and not self.sight_deprived

    @property
    def ball_absent(self) -> bool:
        """Whether the ball is taken out of the scene (``Senses.NO_BALL``, section IV-A-1)."""
        return self.senses is Senses.NO_BALL


@dataclass
class TrialData:
    """Per-step record of one trial; row t is the state observed at time t * 0.1 s."""

    sector: int
    ball_start: np.ndarray  # (3,) m
    joints: np.ndarray  # (T, 14) rad: the 13 joints and the mean finger flexion
    hand: np.ndarray  # (T, 3) m, centre of the palm's inner face
    shoulder: np.ndarray  # (T, 3) m
    ball: np.ndarray  # (T, 3) m; ball-absent (Senses.NO_BALL): where it would hang
    contacts: np.ndarray  # (T, 16) bool, per hand segment (icub.HAND_SEGMENTS), inner faces
    sensors: np.ndarray  # (T, 25) the network's inputs
    hidden: np.ndarray  # (T, 8) internal neuron states
    motor: np.ndarray  # (T, 14) motor neuron states in [0, 1]
    targets: np.ndarray  # (T, 14) motor targets sent to the world, in [-1, 1]
    p_sight: np.ndarray  # (T,)
    p_touch: np.ndarray  # (T,)
    p_multimodal: np.ndarray  # (T,)
    dofs: np.ndarray  # (T, ndof) rad, every joint of the skeleton (to draw the robot)
    #: (T, 16) bool, per hand segment, touches on any face (the reach of IV-A-1); None in a
    #: trial read back from a recording of layout <= 3 (which holds inner-face touches only).
    contacts_any: np.ndarray | None = None
    #: (T, 3) unit vector, world direction of the palm's inner face (+z = palm up); None when
    #: unknown (a trial read back from a recording).
    palm_normal: np.ndarray | None = None
    diverged: bool = False
    steps_run: int = 0

    @classmethod
    def empty(cls, steps: int, sector: int, ball_start: np.ndarray, n_dofs: int = 0
              ) -> "TrialData":
        z = lambda *shape: np.zeros((steps, *shape))  # noqa: E731
        return cls(sector, np.asarray(ball_start, float).copy(), z(N_MOTORS), z(3), z(3), z(3),
                   np.zeros((steps, N_SEGMENTS), bool), z(N_SENSORS), z(N_HIDDEN), z(N_MOTORS),
                   z(N_MOTORS), np.zeros(steps), np.zeros(steps), np.zeros(steps), z(n_dofs),
                   np.zeros((steps, N_SEGMENTS), bool), z(3))

    @property
    def fitness(self) -> float:
        """Mean p_multimodal over the trial's steps; 0 for a diverged trial."""
        return 0.0 if self.diverged else float(self.p_multimodal.mean())


@dataclass
class Lifetime:
    """One lifetime of an individual (section III-C): its fitness and its trials."""

    fitness: float
    trials: list[TrialData] = field(default_factory=list)

    @property
    def diverged(self) -> bool:
        return any(t.diverged for t in self.trials)


class Trial:
    """Runs trials of one network in one world. Build once, run many (buffers are reused for
    the observation; each recorded trial gets its own ``TrialData``).

    The per-step work is its ``steps`` (``steps.TrialSteps``), chosen at construction by the
    config's numerics (``steps_for``): ``compiled_trial.CompiledSteps`` (the living model,
    versions 2 and 3) or version 1's frozen ``reference.steps.ReferenceSteps``. Two ways through
    the same steps: ``run`` keeps every per-step record (post-evaluation, recordings);
    ``fitness`` keeps only what the fitness needs (the genetic algorithm). Both sense the world
    and compute the fitness terms with the same step functions, so a trial's fitness is the same
    to the last bit either way; the Gymnasium environment steps a trial with ``begin``,
    ``observe`` and ``control``."""

    def __init__(self, world: World, config: TrialConfig = TrialConfig()):
        self.world, self.config = world, config
        #: the step functions of this trial's numerics
        self.steps: TrialSteps = steps_for(world, config)
        self._n_steps = config.steps
        self._p = np.zeros(config.steps)  # p_multimodal per step of ``fitness``
        # the steps' functions the control step calls, looked up once
        steps = self.steps
        self._command, self._advance = steps.command, steps.advance
        self._sense, self._observe = steps.sense, steps.observe

    # ------------------------------------------------------------------ one control step
    def sense(self) -> bool:
        """The steps' ``sense``: the sensor vector (``steps.x``) and the fitness terms of the
        state reached; False when it is not finite."""
        return self._sense()

    def observe(self, data: TrialData, t: int) -> bool:
        """The steps' ``observe``: ``sense``, and the world and the sensors into ``data``'s
        row ``t``; False when the state read is not finite."""
        return self._observe(data, t)

    def command(self, targets: np.ndarray) -> None:
        """The steps' ``command``: the motors commanded toward 14 finite targets in [-1, 1]."""
        self._command(targets)

    def control(self, targets: np.ndarray, data: TrialData | None, t: int) -> bool:
        """One control step, the one ``run``, ``fitness`` and the Gymnasium environment take:
        the world driven for one control period (0.1 s) toward ``targets`` (finite, in
        [-1, 1]), then the state it reaches read as step ``t``'s input: into ``data``'s row
        ``t`` (``observe``), or without a record into the sensor vector and the fitness terms
        only (``sense``). After the trial's last step (``t`` = ``config.steps``) nothing is
        read. False when the state read is not finite."""
        self._command(targets)
        self._advance()
        if t == self._n_steps:
            return True
        return self._sense() if data is None else self._observe(data, t)

    # ------------------------------------------------------------------ one trial
    def reset(self, ball_position) -> None:
        """The world at a trial's start: home posture, the ball at rest at ``ball_position``
        (m; parked away when it is absent)."""
        self.steps.reset(ball_position)

    def begin(self, sector: int, ball_position) -> TrialData:
        """Start a trial: the world reset with the ball at ``ball_position`` (in ``sector``)
        and the trial's empty record. ``run`` and the Gymnasium environment (``envs``) then
        step it: ``observe`` row 0, then per step the motor targets and ``control``."""
        self.steps.reset(ball_position)
        return TrialData.empty(self.config.steps, sector, ball_position,
                               self.world.robot.getNumDofs())

    def run(self, network: Network, sector: int, ball_position) -> TrialData:
        """One trial of ``config.steps`` steps with the ball at ``ball_position`` (in
        ``sector``), every per-step record kept. The network is reset to the state that holds
        the home posture."""
        steps = self.steps
        data = self.begin(sector, ball_position)
        network.reset(motor=steps.home_motor)
        x, targets, targets_of, control = steps.x, steps.targets, steps.targets_of, self.control
        finite = self._observe(data, 0)
        for t in range(self.config.steps):
            if not finite:  # the last physics step exploded
                data.diverged = True
                break
            motor = network.step(x)
            finite_targets = targets_of(motor)
            data.hidden[t] = network.hidden
            data.motor[t] = motor
            data.targets[t] = targets
            data.steps_run = t + 1
            if not finite_targets:
                data.diverged = True
                break
            finite = control(targets, data, t + 1)
        return data

    def fitness(self, network: Network, ball_position) -> float:
        """The fitness of the trial ``run`` would run with the ball at ``ball_position`` (mean
        p_multimodal over its steps, 0 when it diverges; section III-C), to the last bit,
        keeping no record: what the genetic algorithm needs."""
        steps = self.steps
        p, targets, control = self._p, steps.targets, self.control
        steps.reset(ball_position)
        network.reset(motor=steps.home_motor)
        fused = steps.fitness(network, p)
        if fused is not None:
            return fused
        act = steps.act
        finite = self._sense()
        for t in range(self.config.steps):
            if not finite:
                return 0.0
            p[t] = steps.p_multimodal
            if not act(network):
                return 0.0
            finite = control(targets, None, t + 1)
        return float(p.mean())

    @property
    def p_series(self) -> np.ndarray:
        """p_multimodal per step of the last ``fitness`` (a view of the trial's buffer; the
        steps after a divergence hold an earlier trial's values)."""
        return self._p


def steps_for(world: World, config: TrialConfig) -> TrialSteps:
    """The steps of ``config.numerics`` (``versions.Numerics``) in ``world``: the living
    model's ``compiled_trial.CompiledSteps`` or version 1's frozen ``reference.steps.
    ReferenceSteps``."""
    if config.numerics is Numerics.COMPILED:
        from .compiled_trial import CompiledSteps  # loads Numba: only for the living model
        return CompiledSteps(world, config)
    require_pinned_kernels()  # version 1 rounds with numpy's kernels: refuse unpinned ones
    from .reference.steps import ReferenceSteps  # only for version 1's runs
    return ReferenceSteps(world, config)


def trial_positions(world: World, rng: np.random.Generator, trials: int = 18
                    ) -> list[tuple[int, np.ndarray]]:
    """(sector, ball position) of each trial of a lifetime: the sectors in turn (18 trials =
    2 per sector, section III-C), each at a random point of the sector. When ``trials`` is not a
    multiple of 9 the turn starts at a random sector, so no sector is favoured on average."""
    start = int(rng.integers(N_SECTORS)) if trials % N_SECTORS else 0
    sectors = [(start + i) % N_SECTORS for i in range(trials)]
    return [(k, world.random_sector_point(k, rng)) for k in sectors]


def network_for(params: NetworkParams, config: TrialConfig) -> Network:
    """The network of ``params`` in the maturational state of ``config`` (reflexes, frozen
    internal neurons, the reflex motors' inputs), computed by its numerics: the living
    model's ``kernels.network.CompiledNetwork`` or version 1's frozen ``reference.network.
    ReferenceNetwork``."""
    if config.numerics is Numerics.COMPILED:
        from .kernels.network import CompiledNetwork as kind  # Numba: the living model only
    else:
        from .reference.network import ReferenceNetwork as kind  # only for version 1's runs
    return kind(params, reflexes=config.reflexes, hidden_frozen=config.hidden_frozen,
                   reflex_inputs=config.reflex_inputs)


def lifetime(params: NetworkParams, world: World, config: TrialConfig,
             rng: np.random.Generator, trial: Trial | None = None) -> Lifetime:
    """One lifetime of a network (section III-C): its ``config.trials`` trials (18) at the
    positions ``rng`` draws, and its fitness, the mean p_multimodal over them."""
    trial = trial if trial is not None and trial.config == config else Trial(world, config)
    network = network_for(params, config)
    trials = [trial.run(network, k, p)
              for k, p in trial_positions(world, rng, config.trials)]
    return Lifetime(float(np.mean([t.fitness for t in trials])), trials)
