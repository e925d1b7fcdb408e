"""The paper's trial as a Gymnasium environment, ``dart_reach/ReachGrasp-v2`` (sections III-B,
III-C, III-D; docs/guides/gymnasium.md). The spaces, rewards and episode end are told once, in
``ReachGraspEnv``'s docstring.

One episode is one trial of ``model.task.Trial``, stepped by the same code: ``Trial.begin``
resets the world, ``Trial.observe`` reads the sensors and the fitness terms into the trial's
record, the action is the motor targets ``ctrnn.motor_targets`` gives the network's motor
outputs, and ``Trial.control``, the control step ``Trial.run`` and ``Trial.fitness`` take,
drives the world for 0.1 s and reads the state it reaches. Nothing of the task is implemented
here a second time: a network stepped through the environment (``policy.NetworkPolicy``) earns
the fitness ``Trial.run`` gives it, bit for bit (tests/envs/test_reach_grasp.py).
"""

from __future__ import annotations

import math
from dataclasses import replace

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.error import ResetNeeded

from ..evolution.conditions import Phase, condition_names, load_condition
from ..evolution.settings import Settings, trial_config
from ..measures.contacts import first_grasp, first_touch
from ..model.ctrnn import N_MOTORS, N_SENSORS, motor_targets, reflex_biases, zero_params
from ..model.versions import CURRENT_MODEL_VERSION
from ..model.scenes import load_scene
from ..model.task import Senses, Trial, TrialData, network_for, trial_positions
from ..model.world import N_SECTORS, World, WorldConfig, check_sector

_REFLEX_MASK = reflex_biases()[0]
#: Indices of the motors the reflexes drive (neck_yaw, neck_pitch, r_hand_fingers): the
#: action's entries there are ignored while the reflexes are on.
REFLEX_MOTORS = np.flatnonzero(_REFLEX_MASK)
#: The options ``reset`` accepts.
RESET_OPTIONS = ("sector", "ball_position")
#: m: how far a ``ball_position`` given to ``reset`` may lie outside its sector's patch of the
#: sphere (off the sphere, or beyond an edge along it) and still be accepted: rounding, not a
#: second scene.
SECTOR_TOLERANCE = 1e-3
#: ``info["reason"]`` of an episode ended by a divergence.
DIVERGED = ("the physics diverged: the world's state after this step is not finite (NaN or "
            "infinite joint or ball positions); the trial scores 0, as in Trial.run")


def shipped_phases() -> dict[str, Phase]:
    """Every phase of the shipped conditions by name (``pre-h`` is the same phase in the
    ``pre-h`` and ``gross-h`` conditions)."""
    return {p.name: p for c in condition_names() for p in load_condition(c).phases}


def check_ball_position(world: World, sector: int, position) -> np.ndarray:
    """``position`` (m, world frame) as a float array, checked to lie in ``sector`` of the
    world's scene (``WorldConfig.sectors``): on the sphere of the sectors' radius around the
    neck and inside the sector's azimuth and elevation edges, each within
    ``SECTOR_TOLERANCE``. ValueError, with where the point is, otherwise."""
    p = np.asarray(position, dtype=float)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise ValueError(f"reset option 'ball_position' must be 3 finite numbers (m, world "
                         f"frame), got {position!r}")
    config = world.config.sectors
    d = p - world.neck_centre
    r = float(np.linalg.norm(d))
    row, col = divmod(int(sector), 3)
    az0, az1 = config.azimuth_edges[col], config.azimuth_edges[col + 1]
    el0, el1 = config.elevation_edges[row], config.elevation_edges[row + 1]
    # +x of the world is backward, +y the robot's right, +z up (world.sphere_point)
    az = math.degrees(math.atan2(d[1], -d[0])) if r > 0 else math.nan
    el = math.degrees(math.asin(max(-1.0, min(1.0, d[2] / r)))) if r > 0 else math.nan
    angle = math.degrees(SECTOR_TOLERANCE / config.radius)  # the tolerance along the sphere
    if not (abs(r - config.radius) <= SECTOR_TOLERANCE and az0 - angle <= az <= az1 + angle
            and el0 - angle <= el <= el1 + angle):
        raise ValueError(
            f"reset option 'ball_position' {p.tolist()} is not in sector {sector}: it lies "
            f"{r:.4f} m from the neck at azimuth {az:.2f} deg and elevation {el:.2f} deg, where "
            f"the sector is the sphere of radius {config.radius} m at azimuth {az0}..{az1} deg "
            f"and elevation {el0}..{el1} deg (tolerance {SECTOR_TOLERANCE} m); "
            f"World.sector_point gives its points")
    return p


def _check_sector(sector) -> int:
    if isinstance(sector, (bool, np.bool_)):
        raise ValueError(f"reset option 'sector' must be an integer in 0..{N_SECTORS - 1}, "
                         f"got the bool {sector!r}")
    check_sector(sector)
    return int(sector)


class ReachGraspEnv(gym.Env):
    """One trial of the paper's reach-and-grasp task per episode: ``dart_reach/ReachGrasp-v2``.

    ## Description

    A simulated iCub (DART physics; torso 3, neck 3, right arm 7, one hand motor) faces a ball
    hanging in one of 9 sectors in front of its right shoulder (Fig. 2) and is rewarded for
    seeing it at the centre of its view and touching it with its hand (Eq. 5), as the evolved
    controllers of Savastano & Nolfi (2013) are. The maturational state is a phase of the
    paper (``phase``): its visual acuity, offset sensors and reflexes.

    ## Action Space

    ``Box(-1, 1, (14,), float32)``: the motor targets, one per motor in
    ``ctrnn.MOTOR_NAMES`` order (neck 3, torso 3, arm 7, hand 1): each joint's desired angle
    scaled into its limits (-1 the lower limit, 1 the upper), which its spring-damper then
    follows at most ``max_joint_speed``. A controller network's motor neuron output s in
    [0, 1] is the action ``a = 2 s - 1`` (``ctrnn.motor_targets``; ``policy.NetworkPolicy``).
    The step uses the given values exactly: float32 actions (exact in float64) and float64
    actions are both taken as they are, never rounded to float32, so a network's float64
    targets drive the world to the last bit. Values outside [-1, 1] are clipped; a
    non-finite value or a wrong shape is a ValueError. While the reflexes are on, the entries
    ``REFLEX_MOTORS`` (neck yaw and pitch, the hand) are ignored: the reflex arcs set them.

    ## Observation Space

    ``Box(-1, 1, (25,), float64)``: the network's 25 sensors in ``ctrnn.SENSOR_NAMES``
    order: 14 proprioceptors (joint angles scaled into [-1, 1]), 6 touch sensors (palm and
    fingertips; -1 or 1), sight x, y and distance with the phase's acuity (Eqs. 1-3), 2
    sight offsets (Eq. 4; 0, "nothing seen", in phases without them). float64, not float32:
    these are the values the controller networks act on, and a network fed float32-rounded
    sensors is another controller (it would not earn its trial's fitness bit for bit);
    learners that want float32 cast them (stable-baselines3 does). Each is a read-only view of
    the trial's record row (nothing copied per step; ``trial_data.sensors``); the last one is
    a copy.

    ## Rewards

    Step k's reward is p_multimodal (Eq. 5) of the state observed at step k, in which the
    action is chosen: min(p_sight, p_touch), in [0, 1], where p_sight is 1 with the ball at the
    centre of the view falling to 0 at its corners and p_touch the share of hand segments
    touching it on their inner faces (``model.sensors``); ``info`` holds both terms. The
    rewards of a whole episode are the trial's ``p_multimodal`` row by row and their mean is
    its fitness (``info["fitness"]``). A step whose physics diverges earns 0 and ends the
    episode (below); the trial's fitness is then 0, as in the GA.

    ## Starting State

    The home posture, at rest, with the ball at rest in a sector: by default a sector at
    random and a point uniformly in its azimuth and elevation, drawn as a GA trial's
    (``task.trial_positions``, one trial) from the environment's generator (``seed``).
    ``reset(options=...)`` may fix them: ``{"sector": k}`` (an int 0-8; a random point of
    sector k) or ``{"sector": k, "ball_position": [x, y, z]}`` (m, world frame, in sector k of
    the scene within ``SECTOR_TOLERANCE``). ``info`` at reset: ``sector``, ``ball_position``
    and ``home_action``, the action that holds the home posture.

    ## Episode End

    - Truncation: after ``steps`` steps (200, the trial's 20 s; ``max_episode_steps=200`` in
      the registration). The observation does not show the time, so the end is a time limit.
    - Termination: when the physics diverges (a non-finite state after a step; rare, a few in
      a million steps of random actions). That step's reward is 0, ``info["diverged"]`` is
      True and ``info["reason"]`` says why; the observation returned is the last finite one
      (the one the action was chosen in), so that no NaN reaches a learner.
    - At either end ``info`` holds ``fitness`` (mean p_multimodal, 0 when diverged),
      ``diverged``, and the measures of the trial as the post-evaluation takes them
      (``measures.metrics``, section IV-A): ``reached`` (some face of the hand touched the
      ball at an observed step), ``grasped`` (the palm and a finger touched it on their inner
      faces at one step) and ``is_success`` (= ``grasped``: the task is to reach and grasp).

    ## Arguments

    - ``phase``: a shipped phase's name (``pre``, ``gross``, ``fine``, ``pre-h``,
      ``gross-h``, ``gross-hat``, ``pre-star``, ``gross-hat-star``, ``fine-hat``,
      ``fine-star``) or a ``conditions.Phase``; default ``pre``. Its free groups (which
      parameters evolve) constrain the GA's genome, not an outside learner.
    - ``scene``: a scene name or file (``model.scenes``); None: the model version's scene.
    - ``reflexes``: None as the phase has them; True or False. While on, the environment
      computes the reflex motors' outputs with the network's hand-set reflex weights and
      thresholds (``ctrnn.reflex_weights``; a network of zero parameters, no memory) and they
      replace the action's ``REFLEX_MOTORS`` entries; off, the action drives all 14 motors
      (a network with its reflexes built in is then the whole controller).
    - ``senses``: a post-evaluation sensory condition (``task.Senses`` or its value).
    - ``steps``: control steps of 0.1 s per episode (200); with another value, pass the same
      ``max_episode_steps`` to ``gymnasium.make``.
    - ``model_version``: the model version the trial runs under (``model.levers``; default
      the version new runs train under); a robot trained under version 2 runs under 2.
    - ``render_mode``: None, ``"rgb_array"`` or ``"human"``. ``rgb_array``: ``render()``
      returns a camera image of the scene at the current step, (``height``, ``width``, 3)
      uint8, drawn in numpy from the DART world's shapes (``viewing.camera``: no GPU,
      display or graphics driver; hand segments touching the ball yellow). ``human``: every
      step is streamed to a live Rerun viewer in the trial layout of ``dart-reach watch``
      (``viewing.live``), once its action is taken; ``render()`` returns None.
    - ``width``, ``height``: the ``rgb_array`` image's size in pixels (320 x 240).
    - ``viewer``: where ``human`` streams to: a viewer's gRPC URL
      (``rerun+http://HOST:9876/proxy``), an .rrd path written as the episodes run, or None:
      a viewer spawned on this machine, or, without a display, a gRPC server in this process
      (its URL printed to stderr; ``rerun --connect URL`` watches it).

    ## Version History

    - v2: the model version new runs use by default (3: the scene calibrated on Fig. 5's
      reach, compiled numerics; ``model_version`` selects another); ``dart_reach/ReachGrasp-v1``
      stays registered as this environment on model version 1, the model v1 ran.
    - v1: ``render_mode`` ``"rgb_array"`` a camera image of the scene (it was a screenshot
      of the Rerun viewer's window, which needed a Vulkan driver) and ``"human"``; actions
      in [-1, 1] float32 (the motor targets; v0 took the motor outputs in [0, 1]
      float64), ``max_episode_steps=200`` in the registration, a diverged step rewarded 0
      (v0: minus the return so far) with ``info["reason"]``, inputs checked (``sector`` an
      int, ``ball_position`` in its sector), ``reached``, ``grasped`` and ``is_success`` at
      the end.
    - v0: the first version; ``gymnasium.make`` now refuses it and names v1.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 10}

    def __init__(self, phase: str | Phase = "pre", scene: str | None = None,
                 reflexes: bool | None = None, senses: str | Senses = Senses.NORMAL,
                 steps: int = 200, render_mode: str | None = None, width: int = 320,
                 height: int = 240, viewer: str | None = None,
                 model_version: int = CURRENT_MODEL_VERSION):
        if isinstance(phase, str):
            phases = shipped_phases()
            if phase not in phases:
                raise ValueError(f"unknown phase {phase!r}; shipped phases: "
                                 f"{', '.join(phases)} (or pass a conditions.Phase)")
            phase = phases[phase]
        elif not isinstance(phase, Phase):
            raise TypeError(f"phase must be a phase name or a conditions.Phase, got "
                            f"{type(phase).__name__}")
        if reflexes is not None and not isinstance(reflexes, bool):
            raise TypeError(f"reflexes must be True, False or None (as the phase), got "
                            f"{reflexes!r}")
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise ValueError(f"steps must be a positive integer, got {steps!r}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None, 'rgb_array' or 'human', got "
                             f"{render_mode!r}")
        for name, pixels in (("width", width), ("height", height)):
            if isinstance(pixels, bool) or not isinstance(pixels, (int, np.integer)) \
                    or pixels < 8:
                raise ValueError(f"{name} must be an integer of at least 8 pixels, got "
                                 f"{pixels!r}")
        # kept for pickling: the environment is rebuilt from them (a DART world does not pickle)
        self._arguments = dict(phase=phase, scene=scene, reflexes=reflexes, senses=senses,
                               steps=int(steps), render_mode=render_mode, width=int(width),
                               height=int(height), viewer=viewer, model_version=model_version)
        self.phase = phase
        settings = Settings(steps=int(steps), model_version=model_version)
        config = trial_config(phase, settings)
        self.config = replace(config, senses=Senses(senses), reflexes=(
            config.reflexes if reflexes is None else reflexes))
        self.render_mode = render_mode
        self._renderer = _renderer(render_mode, int(width), int(height), viewer)
        world_config = (settings.world if scene is None
                        else load_scene(scene).world(settings.world))
        self.world = World(world_config)
        self.trial = Trial(self.world, self.config)
        # the reflex arcs alone: hand-set weights and thresholds, no memory (tau 0)
        self._reflex = (network_for(zero_params(), replace(self.config, hidden_frozen=True))
                        if self.config.reflexes else None)
        self.observation_space = spaces.Box(-1.0, 1.0, (N_SENSORS,), np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (N_MOTORS,), np.float32)
        #: the action that holds the home posture (its motor targets)
        self.home_action = self.world.home_targets.copy()
        self._targets = np.zeros(N_MOTORS)
        self._motor = np.zeros(N_MOTORS)
        self._reflex_targets = np.zeros(N_MOTORS)
        self._final = TrialData.empty(1, 0, np.zeros(3), self.world.robot.getNumDofs())
        self._data: TrialData | None = None
        self._t = 0
        #: the seed of the last ``reset`` (None: it went on with the generator)
        self.episode_seed: int | None = None

    def __reduce__(self):
        """Pickled as its arguments and its registration's spec (a DART world does not
        pickle): the copy is a new environment, to be reset before it steps."""
        return (_rebuild, (self._arguments, self.spec))

    @property
    def trial_data(self) -> TrialData | None:
        """The record of the current episode (``task.TrialData``, as ``Trial.run`` fills it;
        ``hidden`` stays 0: the environment does not know a policy's internal state;
        ``targets`` holds the actions as applied, reflexes included, and ``motor`` the motor
        outputs they stand for, (a + 1) / 2). None before ``reset``."""
        return self._data

    # ------------------------------------------------------------------ episodes
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.episode_seed = seed
        sector, position = self._ball(options or {})
        self._data = data = self.trial.begin(sector, position)
        self._t = 0
        if not self.trial.observe(data, 0):
            raise RuntimeError("the world's state is not finite right after a reset")
        info = {"sector": sector, "ball_position": data.ball_start.copy(),
                "home_action": self.home_action.copy()}
        observation = data.sensors[0]
        observation.flags.writeable = False
        if self.render_mode == "human":
            self._renderer.send(self.world, data, self.recording_info())
        return observation, info

    def _ball(self, options) -> tuple[int, np.ndarray]:
        if not isinstance(options, dict):
            raise TypeError(f"reset options must be a dict, got {type(options).__name__}")
        unknown = sorted(set(options) - set(RESET_OPTIONS))
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; options: "
                             f"{', '.join(RESET_OPTIONS)}")
        if "ball_position" in options and "sector" not in options:
            raise ValueError("reset option 'ball_position' needs its 'sector' (0-8)")
        if "sector" not in options:
            return trial_positions(self.world, self.np_random, trials=1)[0]
        sector = _check_sector(options["sector"])
        if "ball_position" not in options:
            return sector, self.world.random_sector_point(sector, self.np_random)
        return sector, check_ball_position(self.world, sector, options["ball_position"])

    def step(self, action):
        data, t = self._data, self._t
        if data is None or t >= self.config.steps or data.diverged:
            raise ResetNeeded("the episode is over (or has not begun): call reset()")
        if np.shape(action) != (N_MOTORS,):
            raise ValueError(f"the action must have shape ({N_MOTORS},), got {np.shape(action)}")
        targets, motor = self._targets, self._motor
        targets[:] = action  # float32 and float64 alike, exactly (float64 holds both)
        if not math.isfinite(targets.sum()):
            raise ValueError(f"the action must be 14 finite numbers in [-1, 1], got {action!r}")
        np.clip(targets, -1.0, 1.0, out=targets)
        np.add(targets, 1.0, out=motor)
        motor *= 0.5  # the motor outputs the targets stand for (the record's ``motor``)
        if self._reflex is not None:  # the reflex arcs' outputs and their targets, as a network's
            reflex = self._reflex.step(data.sensors[t])
            np.copyto(motor, reflex, where=_REFLEX_MASK)
            np.copyto(targets, motor_targets(reflex, out=self._reflex_targets), where=_REFLEX_MASK)
        # as Trial.run: record, then its one control step (Trial.control); after the last
        # step the state reached is read into a record of its own, the final observation
        data.motor[t] = motor
        data.targets[t] = targets
        data.steps_run = t + 1
        reward = float(data.p_multimodal[t])
        self._t = t = t + 1
        last = t == self.config.steps
        ok = self.trial.control(targets, self._final if last else data, 0 if last else t)
        # a read-only view of the record's row (the last one: a copy, its buffer is reused)
        observation = self._final.sensors[0].copy() if last else data.sensors[t]
        observation.flags.writeable = False
        info = {"p_sight": float(data.p_sight[t - 1]), "p_touch": float(data.p_touch[t - 1])}
        if not ok:  # the record ends before the state that is not finite, as Trial.run's
            data.diverged = True
            reward = 0.0
            info["reason"] = DIVERGED
            observation = data.sensors[t - 1]  # the last finite one, not NaNs for a learner
        if last or not ok:
            info.update(self._outcome(data))
        if self.render_mode == "human":
            self._renderer.send(self.world, data, self.recording_info())
        return observation, reward, not ok, last and ok, info

    @staticmethod
    def _outcome(data: TrialData) -> dict:
        """The episode's end: its fitness and, as ``measures.metrics.trial_metrics`` takes them
        (the observed steps), whether the hand reached and grasped the ball."""
        n = data.steps_run
        reached = first_touch(data.contacts_any[:n]) >= 0
        grasped = first_grasp(data.contacts[:n]) >= 0
        return {"fitness": data.fitness, "diverged": data.diverged, "reached": reached,
                "grasped": grasped, "is_success": grasped}

    # ------------------------------------------------------------------ seeing
    def recording_info(self):
        """What a recording of the current episode is about (``recording.layout.TrialInfo``): the
        phase, the sector, the reset's seed ("drawn": the environment's generator went on)."""
        from ..recording.rrd import TrialInfo  # rerun and polars: about a second to import

        if self._data is None:
            raise ResetNeeded("no episode before reset()")
        seed = "drawn" if self.episode_seed is None else str(self.episode_seed)
        return TrialInfo(CONDITION, self.phase.name, 0, 0, self._data.sector, 0, seed,
                         senses=self.config.senses.value)

    def render(self):
        """``rgb_array``: the camera's image (H, W, 3) uint8 of the scene at the current step
        (``viewing.episode.TrialRenderer``). None without a render mode, and in ``human``
        mode, whose frames ``reset`` and ``step`` stream as they run."""
        if self.render_mode != "rgb_array":
            return None
        if self._data is None:
            raise ResetNeeded("nothing to render before reset()")
        data, t = self._data, self._t
        # the contacts of the state the world holds: the record's row t, the last one apart
        if data.diverged:
            touching = data.contacts[t - 1]
        else:
            touching = self._final.contacts[0] if t == self.config.steps else data.contacts[t]
        return self._renderer.frame(self.world, touching)

    def close(self):
        if self._renderer is not None:
            self._renderer.close()
        super().close()


#: The ``condition`` an episode's recording names (its ``phase`` is the environment's).
CONDITION = "gymnasium"


def _rebuild(arguments: dict, spec) -> ReachGraspEnv:
    env = ReachGraspEnv(**arguments)
    env.spec = spec
    return env


def _renderer(mode: str | None, width: int, height: int, viewer):
    """The renderer of a render mode, loaded only when one asks for it: ``human``'s stream
    loads rerun and polars (about a second), which every process of a vector environment
    would pay."""
    if mode == "rgb_array":
        from ..viewing.episode import TrialRenderer
        return TrialRenderer(width, height)
    if mode == "human":
        from ..viewing.live import LiveViewer
        return LiveViewer(viewer)
    return None
