"""The step functions of a trial behind one interface (sections III-B, III-C).

A ``task.Trial`` is built with the ``TrialSteps`` of its config's numerics (``task.steps_for``):
``compiled_trial.CompiledSteps``, the living model (model versions 2 and 3: the equations
compiled with Numba, ``model.compiled``), or model version 1's frozen ``reference.steps.
ReferenceSteps`` (numpy and Python floats), used only to resume, evaluate and reproduce the
runs trained under version 1.
The genetic algorithm's trial (``Trial.fitness``), the recorded trial (``Trial.run``) and the
Gymnasium environment's step (``envs.reach_grasp``, through ``Trial.begin``, ``Trial.observe``
and ``Trial.control``) all call these, and nothing else, per step.

Per control step of 0.1 s: ``sense`` reads the world into the sensor vector ``x`` (25 values,
layout ``ctrnn.PROPRIO``, ``TOUCH``, ``SIGHT``, ``OFFSET``) and the fitness terms ``p_sight``,
``p_touch``, ``p_multimodal`` (Eq. 5); ``act`` updates the network from ``x`` and writes its
motor targets (14 values in [-1, 1]) into ``targets``; ``command`` sends targets to the motors
(the servo's speed cap, ``WorldConfig.max_joint_speed``) and ``advance`` runs the physics
substeps, gathering the hand's touches. ``observe`` is ``sense`` plus the record's row.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from .ctrnn import N_MOTORS, Network
from .levers import NetworkStart
from .world import World


class TrialSteps(Protocol):
    """What a trial's steps offer, under either numerics. The buffers are the steps' own and
    are updated in place: ``x`` (25,) the sensor vector ``sense`` read last, ``targets`` (14,)
    the motor targets ``act`` or ``targets_of`` wrote last, ``home_motor`` (14,) the network's
    motor states at a trial's start (``levers.NetworkStart``); ``p_sight``, ``p_touch``,
    ``p_multimodal`` the fitness terms ``sense`` computed last (Eq. 5)."""

    x: np.ndarray
    targets: np.ndarray
    home_motor: np.ndarray
    p_sight: float
    p_touch: float
    p_multimodal: float

    def reset(self, ball_position) -> None:
        """The world at a trial's start: home posture, the ball at rest at ``ball_position``
        (m; parked away, ``world.BALL_PARKED``, when the senses say it is absent)."""

    def sense(self) -> bool:
        """The sensors and the fitness terms of the state reached; whether it is finite."""

    def observe(self, data, t: int) -> bool:
        """``sense``, and the world and the sensors into ``data``'s row ``t`` (a
        ``task.TrialData``)."""

    def targets_of(self, motor: np.ndarray) -> bool:
        """``targets`` = 2 motor - 1 (``ctrnn.motor_targets``); whether finite."""

    def act(self, network: Network) -> bool:
        """The network's update from ``x`` and its targets into ``targets``; whether finite."""

    def command(self, targets: np.ndarray) -> None:
        """The motors commanded toward 14 finite targets in [-1, 1]; no physics yet."""

    def advance(self) -> None:
        """The physics substeps of one control period, the touches gathered."""

    def fitness(self, network: Network, p: np.ndarray) -> float | None:
        """``Trial.fitness`` after the reset in a faster form, to the same bits, or None
        when these steps have none for ``network`` (the trial then runs its own loop)."""


def home_motor(world: World, config) -> np.ndarray:
    """The network's motor states at a trial's start under ``config`` (a ``task.TrialConfig``;
    ``levers.NetworkStart``): those whose targets hold the home posture, or 0."""
    return ((world.home_targets + 1.0) / 2.0
            if config.network_start is NetworkStart.HOLD_HOME else np.zeros(N_MOTORS))
