"""The paper's trial as a Gymnasium environment, ``dart_reach/ReachGrasp-v0`` (sections III-B,
III-C, III-D; docs/guides/gymnasium.md).

One episode is one trial of ``model.task.Trial``, stepped by the same code: ``Trial.begin``
resets the world, ``Trial.observe`` reads the sensors and the fitness terms into the trial's
record, ``ctrnn.motor_targets`` turns the motor outputs into joint targets and ``World.step``
runs one control step (0.1 s). Nothing of the task is implemented here a second time: a
network stepped through the environment earns the fitness ``Trial.run`` gives it, bit for bit
(tests/envs/test_reach_grasp.py).

- **Observation**: the network's 25 sensor values (``ctrnn.SENSOR_NAMES``): 14 proprioceptors,
  6 touch sensors, 3 sight sensors with the phase's acuity (Eqs. 1-3), 2 sight-offset sensors
  (Eq. 4; they read 0, "nothing seen", in phases without them). Every value lies in [-1, 1]
  (``model.sensors``): ``Box(-1, 1, (25,), float64)``.
- **Action**: the 14 motor outputs (``ctrnn.MOTOR_NAMES``) in the network's range [0, 1]
  (``Box(0, 1, (14,), float64)``; values outside are clipped into it); target = 2 a - 1, scaled
  into the joint's limits by the world, as the controller's motor neurons (section III-B).
- **Reward**: step k's p_multimodal (Eq. 5), the fitness term of the state observed at step k,
  in which the action is chosen: the rewards of an episode are the trial's ``p_multimodal``
  row by row and their mean is the trial's fitness. A trial whose physics explodes scores 0
  (``Trial.run``): the episode then terminates and its last reward cancels the return so far.
- **Observations** are read-only views of the trial's record (``trial_data.sensors``), so that
  nothing is copied per step and no learner's in-place normalisation corrupts the record.
- **Episode end**: ``truncated`` after ``steps`` steps (200, 20 s; the observation does not
  show the time, so the end of a trial is a time limit); ``terminated`` only on divergence.
  The last observation is read from the world after the last step; the trial itself never
  reads it.
- **Reset**: the ball's sector and position are drawn as a GA trial's
  (``task.trial_positions`` with one trial: a sector at random, a point uniformly in its
  azimuth and elevation) from the environment's generator; ``options`` may fix them:
  ``{"sector": k}`` (a random point of sector k) or ``{"sector": k, "ball_position": p}``.
  ``info["home_action"]`` is the action that holds the home posture, the state a network
  starts a trial in (``Trial.run``).
- **Reflexes** (sections II-D, III-D 1): in the network, the orienting reflexes drive the neck
  yaw and pitch motor neurons and the grasp reflex the hand's, through hand-set connections
  and thresholds that replace the evolved direct ones (``ctrnn.reflex_weights``). While the
  environment's reflexes are on, it computes those three motor outputs with the same
  hand-set weights and thresholds (a ``ctrnn.Network`` of zero parameters, reflexes on, no
  memory) and they replace the action's entries ``REFLEX_MOTORS``, which are ignored: the
  policy plays the evolved part of the controller of a robot whose reflexes are hand-set.
  Unlike an evolved network from gross-reaching on, a policy cannot add to the reflex
  neurons' input (the internal neurons' projection, III-D 2) nor slow them (their evolved
  time constants). With ``reflexes=False`` the action drives all 14 motors: a network that
  has its reflexes built in (``task.network_for``) is then the whole controller.
- **Phase** (the maturational state, III-D and Fig. 10): a phase name of a shipped condition
  (``pre``, ``gross``, ``fine``, ``pre-h``, ``gross-h``, ``gross-hat``, ``pre-star``,
  ``gross-hat-star``, ``fine-hat``, ``fine-star``) or a ``conditions.Phase``: its acuity,
  offset sensors and reflexes. Which parameters may learn in a phase (its free groups, the
  frozen internal neurons of pre-reaching) constrain the GA's genome, not an outside learner.
- **Scene**: a shipped scene name or a scene file (``model.scenes``); ``senses``: a
  post-evaluation condition (``task.Senses``, IV-B).
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
from ..model.ctrnn import N_MOTORS, N_SENSORS, Network, motor_targets, reflex_biases, zero_params
from ..model.scenes import load_scene
from ..model.task import Senses, Trial, TrialData, trial_positions
from ..model.world import World, WorldConfig, check_sector

_REFLEX_MASK = reflex_biases()[0]
#: Indices of the motors the reflexes drive (neck_yaw, neck_pitch, r_hand_fingers): the
#: action's entries there are ignored while the reflexes are on.
REFLEX_MOTORS = np.flatnonzero(_REFLEX_MASK)
#: The options ``reset`` accepts.
RESET_OPTIONS = ("sector", "ball_position")


def shipped_phases() -> dict[str, Phase]:
    """Every phase of the shipped conditions by name (``pre-h`` is the same phase in the
    ``pre-h`` and ``gross-h`` conditions)."""
    return {p.name: p for c in condition_names() for p in load_condition(c).phases}


class ReachGraspEnv(gym.Env):
    """One trial of the reach-and-grasp task per episode (see the module docstring).

    Arguments: ``phase`` (a shipped phase's name or a ``Phase``; default pre-reaching),
    ``scene`` (a scene name or file; None: the default scene), ``reflexes`` (None: as the
    phase has them), ``senses`` (``task.Senses`` or its value), ``steps`` (control steps of
    0.1 s per episode), ``render_mode`` (None or ``"rgb_array"``: a frame drawn by the real
    Rerun viewer, headless; needs a Vulkan driver, RuntimeError at construction where there
    is none). Builds its own DART world (about 0.2 s).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, phase: str | Phase = "pre", scene: str | None = None,
                 reflexes: bool | None = None, senses: str | Senses = Senses.NORMAL,
                 steps: int = 200, render_mode: str | None = None):
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
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.phase = phase
        config = trial_config(phase, Settings(steps=int(steps)))
        self.config = replace(config, senses=Senses(senses), reflexes=(
            config.reflexes if reflexes is None else reflexes))
        self.render_mode = render_mode
        if render_mode is not None:
            self._renderer = _renderer()
        world_config = WorldConfig() if scene is None else load_scene(scene).world()
        self.world = World(world_config)
        self.trial = Trial(self.world, self.config)
        # the reflex arcs alone: hand-set weights and thresholds, no memory (tau 0)
        self._reflex = (Network(zero_params(), reflexes=True, hidden_frozen=True)
                        if self.config.reflexes else None)
        self.observation_space = spaces.Box(-1.0, 1.0, (N_SENSORS,), np.float64)
        self.action_space = spaces.Box(0.0, 1.0, (N_MOTORS,), np.float64)
        self.home_action = (self.world.home_targets + 1.0) / 2.0
        self._action = np.zeros(N_MOTORS)
        self._targets = np.zeros(N_MOTORS)
        self._final = TrialData.empty(1, 0, np.zeros(3), self.world.robot.getNumDofs())
        self._data: TrialData | None = None
        self._t = 0
        self._return = 0.0
        #: the seed of the last ``reset`` (None: it went on with the generator)
        self.episode_seed: int | None = None

    @property
    def trial_data(self) -> TrialData | None:
        """The record of the current episode (``task.TrialData``, as ``Trial.run`` fills it;
        ``hidden`` stays 0: the environment does not know a policy's internal state;
        ``motor`` holds the actions as applied, reflexes included). None before ``reset``."""
        return self._data

    # ------------------------------------------------------------------ episodes
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.episode_seed = seed
        sector, position = self._ball(options or {})
        self._data = data = self.trial.begin(sector, position)
        self._t, self._return = 0, 0.0
        if not self.trial.observe(data, 0):
            raise RuntimeError("the world's state is not finite right after a reset")
        info = {"sector": sector, "ball_position": data.ball_start.copy(),
                "home_action": self.home_action.copy()}
        observation = data.sensors[0]
        observation.flags.writeable = False
        return observation, info

    def _ball(self, options: dict) -> tuple[int, np.ndarray]:
        unknown = sorted(set(options) - set(RESET_OPTIONS))
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; options: "
                             f"{', '.join(RESET_OPTIONS)}")
        if "ball_position" in options and "sector" not in options:
            raise ValueError("reset option 'ball_position' needs its 'sector' (0-8)")
        if "sector" not in options:
            return trial_positions(self.world, self.np_random, trials=1)[0]
        sector = options["sector"]
        check_sector(sector)
        if "ball_position" not in options:
            return int(sector), self.world.random_sector_point(sector, self.np_random)
        position = np.asarray(options["ball_position"], dtype=float)
        if position.shape != (3,) or not np.isfinite(position).all():
            raise ValueError(f"reset option 'ball_position' must be 3 finite numbers (m, world "
                             f"frame), got {options['ball_position']!r}")
        return int(sector), position

    def step(self, action):
        data, t = self._data, self._t
        if data is None or t >= self.config.steps or data.diverged:
            raise ResetNeeded("the episode is over (or has not begun): call reset()")
        a = self._action
        if np.shape(action) != (N_MOTORS,):
            raise ValueError(f"the action must have shape ({N_MOTORS},), got {np.shape(action)}")
        a[:] = action
        if not math.isfinite(a.sum()):
            raise ValueError(f"the action must be 14 finite numbers in [0, 1], got {action!r}")
        np.clip(a, 0.0, 1.0, out=a)
        if self._reflex is not None:
            np.copyto(a, self._reflex.step(data.sensors[t]), where=_REFLEX_MASK)
        # as Trial.run: record, targets, one control step, observe the next state
        targets = motor_targets(a, out=self._targets)
        data.motor[t] = a
        data.targets[t] = targets
        data.steps_run = t + 1
        reward = float(data.p_multimodal[t])
        self.world.step(targets)
        self._t = t = t + 1
        last = t == self.config.steps
        ok = self.trial.observe(self._final if last else data, 0 if last else t)
        # a read-only view of the record's row (the last one: a copy, its buffer is reused)
        observation = self._final.sensors[0].copy() if last else data.sensors[t]
        observation.flags.writeable = False
        info = {"p_sight": float(data.p_sight[t - 1]), "p_touch": float(data.p_touch[t - 1])}
        if not ok:
            data.diverged = True
            reward = -self._return
        self._return += reward
        if last or not ok:
            info.update(fitness=data.fitness, diverged=data.diverged)
        return observation, reward, not ok, last and ok, info

    # ------------------------------------------------------------------ seeing
    def render(self):
        """An RGB frame (H, W, 3) uint8 of the episode so far at its current step, drawn by the
        real Rerun viewer (headless) with the trial layout; None without a render mode."""
        if self.render_mode is None:
            return None
        if self._data is None:
            raise ResetNeeded("nothing to render before reset()")
        return self._renderer.frame(self)

    def close(self):
        if self.render_mode is not None:
            self._renderer.close()
        super().close()


def _renderer():
    """The headless renderer (``envs.seeing``), loaded only when a render mode asks for it:
    rerun, polars and the viewer take about a second to import."""
    from .seeing import Renderer
    return Renderer()
