"""A controller network as a policy of ``ReachGraspEnv``: a shipped evolved robot (or any
``ctrnn.Network``) acting through the environment, earning there the fitness its trial gives
it, bit for bit (docs/guides/gymnasium.md).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..evolution.genome import decode
from ..evolution.settings import Settings, trial_config
from ..model.ctrnn import N_MOTORS, Network, motor_targets
from ..model.task import network_for
from .reach_grasp import shipped_phases

if TYPE_CHECKING:  # robots reads run directories: not needed to step a network
    from ..robots import ShippedRobot


class NetworkPolicy:
    """``network`` as a policy: ``reset(info)`` at each episode's start (the network's state
    that holds the home posture, as ``Trial.run`` sets it, from ``info["home_action"]``), then
    ``policy(observation)`` for each action, the motor targets of the network's outputs
    (``ctrnn.motor_targets``: a = 2 s - 1, float64, the values the trial sends the world).
    The returned array is reused from step to step: copy it to keep it."""

    def __init__(self, network: Network):
        if not isinstance(network, Network):
            raise TypeError(f"network must be a ctrnn.Network, got {type(network).__name__}")
        self.network = network
        self._action = np.zeros(N_MOTORS)

    @classmethod
    def of_robot(cls, robot: ShippedRobot) -> "NetworkPolicy":
        """The network of a shipped robot (``dart_reach.robots.robots``) in its phase's
        maturational state, reflexes built in, computed by the numerics of the model version
        it was trained under: to reproduce its trials, step it through an environment of the
        same phase and version with the environment's reflexes off (``ReachGraspEnv(phase=
        robot.phase, reflexes=False, model_version=robot.model_version)``)."""
        phases = shipped_phases()
        if robot.phase not in phases:
            raise ValueError(f"robot of unknown phase {robot.phase!r}; shipped phases: "
                             f"{', '.join(phases)}")
        phase = phases[robot.phase]
        params = decode(robot.genome, phase.free_groups)
        return cls(network_for(params, trial_config(
            phase, Settings(model_version=robot.model_version))))

    def reset(self, info: dict) -> None:
        """Set the network to the state that holds the home posture (``info`` of
        ``env.reset``)."""
        self.network.reset(motor=(np.asarray(info["home_action"]) + 1.0) / 2.0)

    def __call__(self, observation) -> np.ndarray:
        return motor_targets(self.network.step(observation), out=self._action)
