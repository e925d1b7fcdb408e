"""Model versions and levers: the model's own choices where the paper is silent or torn.

Where the paper fixes a number the model follows it; where it leaves a choice open the model
makes one, and the choices that decide what evolution finds are *levers* a user can set (a
scene or a ``Levers`` value in a run's settings), documented with their units in
docs/model/levers.md. The ball's distance is the scene's sphere radius (``model.scenes``);
self-collision of the robot's body is a physics setting (``world.WorldConfig.self_collision``);
the three levers of the trial are here. A model version (``model.versions``) names a value of
every lever, the scene, self-collision and the numerics as one record.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class ReflexInputs(enum.Enum):
    """What drives the three reflex motor neurons (neck yaw, neck pitch, fingers) besides the
    hand-set reflex arcs (section III-D 1, Fig. 3), while the reflexes are on.

    - ``HAND_SET`` (version 1's default): only the hand-set reflex weights; the evolved direct
      inputs of these three motors are not used.
    - ``EVOLVED``: as Fig. 3's caption reads ("dashed arrows pointing to the motor layer
      indicate connections toward all motor neurons"): every other sensor reaches them too,
      through its evolved weight times ``REFLEX_EVOLVED_SCALE`` (0.1: weights in [-0.5, 0.5]
      instead of [-5, 5]), so that in a random network the 24 evolved inputs sum to about a
      fifth of the grasp reflex's drive and the reflexes still act; the reflex arcs' own
      connections and the thresholds stay hand-set. The scale is this project's choice, fixed
      before any run (docs/model/levers.md gives the drive it measured).
    """

    HAND_SET = "hand-set"
    EVOLVED = "evolved"


#: The factor on the evolved direct weights of the reflex motors under ``ReflexInputs.EVOLVED``.
REFLEX_EVOLVED_SCALE = 0.1


class TouchPay(enum.Enum):
    """How p_touch of Eq. 5 counts touch (section III-C: "p_touch measures the number of inner
    hand/fingers segments in contact with the object ... scaled between 0 and 1").

    - ``FACES`` (version 1's default): n / 16, n the hand segments touching the ball on their
      inner face this step.
    - ``BINARY``: 1 when any inner face touches, else 0 (touch pays by time, not by area).
    - ``CAPPED``: min(n, ``TOUCH_CAP``) / ``TOUCH_CAP``, ``TOUCH_CAP`` = 4 (the palm and three
      finger segments already pay fully; wrapping the whole hand pays no more).
    """

    FACES = "faces"
    BINARY = "binary"
    CAPPED = "capped"


#: Segments from which ``TouchPay.CAPPED`` pays p_touch = 1.
TOUCH_CAP = 4


class NetworkStart(enum.Enum):
    """The network's state at a trial's start (the paper does not say).

    - ``HOLD_HOME`` (version 1's default): internal states 0, motor states (t_home + 1) / 2, the
      states whose targets hold the home posture.
    - ``ZERO``: every state 0 (motor targets -1 until the network's first update moves them).
    """

    HOLD_HOME = "hold-home"
    ZERO = "zero"


#: The trial's levers: field name -> its enum (``Levers``, ``task.TrialConfig``).
TRIAL_LEVERS = {"reflex_inputs": ReflexInputs, "touch_pay": TouchPay,
                "network_start": NetworkStart}


def coerce_levers(config) -> None:
    """In a frozen dataclass's ``__post_init__``: each field of ``TRIAL_LEVERS`` as its enum
    (a value such as "binary" is taken); ``ValueError`` naming the choices otherwise."""
    for name, kind in TRIAL_LEVERS.items():
        value = getattr(config, name)
        if not isinstance(value, kind):
            try:
                object.__setattr__(config, name, kind(value))
            except ValueError:
                raise ValueError(f"{name} must be one of "
                                 f"{', '.join(repr(k.value) for k in kind)}, got {value!r}"
                                 ) from None


@dataclass(frozen=True)
class Levers:
    """The trial's levers (see the enums); the defaults are model version 1's choices."""

    reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET
    touch_pay: TouchPay = TouchPay.FACES
    network_start: NetworkStart = NetworkStart.HOLD_HOME

    def __post_init__(self):
        coerce_levers(self)

    def to_json(self) -> dict:
        return {k: getattr(self, k).value for k in TRIAL_LEVERS}

    @classmethod
    def from_json(cls, d: dict | None) -> "Levers":
        """The inverse of ``to_json``; None or missing keys: version 1's defaults."""
        d = dict(d or {})
        unknown = sorted(set(d) - set(TRIAL_LEVERS))
        if unknown:
            raise ValueError(f"unknown lever(s) {', '.join(unknown)}")
        return cls(**d)

    def changed(self) -> dict[str, str]:
        """The levers set away from version 1's defaults, name -> value."""
        return self.changed_from(Levers())

    def changed_from(self, base: "Levers") -> dict[str, str]:
        """The levers set away from ``base``'s, name -> value."""
        return {k: v for k, v in self.to_json().items() if base.to_json()[k] != v}
