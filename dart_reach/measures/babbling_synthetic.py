"""Synthetic hand paths with known labels, on which the babbling detector
(``kinematics.hand_periodicity``, ``hand_amplitude``, ``is_babbling``) is validated
(docs/model/measures.md, "Validating the detector"; the labels are the protocol's, fixed
before the detector was run on them).

Each path is (``STEPS``, 3) positions in metres at the control step ``kinematics.DT`` about a
point in front of the shoulder. *Babbling* families: ``circle`` (a circle or an ellipse in a
random plane), ``sweep`` (to and fro along a random direction), each also ``interrupted``
(the hand stops where a sweep meets the ball, 0.5-2 s, one to four times): 5-40 cycles in
20 s, a radius (half the sweep) of 0.06-0.20 m, the period wandering by up to 15 % from cycle
to cycle, white noise up to 1 cm and a drift up to 10 cm. *Not babbling*: ``rest``,
``reach and hold``, ``drift``, ``wander`` (smooth random movement without a rhythm),
``small circles`` (radius below 3 cm) and ``slow sweeps`` (at most 2 cycles in 20 s)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics import DT

#: Rows of a path: a 20 s trial at 0.1 s.
STEPS = 200
BABBLING_FAMILIES = ("circle", "sweep", "circle, interrupted", "sweep, interrupted")
STILL_FAMILIES = ("rest", "reach and hold", "drift", "wander", "small circles", "slow sweeps")
FAMILIES = BABBLING_FAMILIES + STILL_FAMILIES
_CENTRE = np.array([0.25, -0.15, 0.55])


@dataclass(frozen=True)
class Path:
    family: str
    babbling: bool
    hand: np.ndarray


def _plane(rng) -> tuple[np.ndarray, np.ndarray]:
    """Two orthonormal directions of a random plane."""
    a, b = np.linalg.qr(rng.normal(size=(3, 3)))[0][:, :2].T
    return a, b


def _phase(rng, cycles: float, wander: float) -> np.ndarray:
    """(STEPS,) phase (rad) of ``cycles`` cycles in 20 s whose rate wanders by up to
    ``wander`` (a fraction) from cycle to cycle, smoothly."""
    knots = max(int(np.ceil(cycles)) + 2, 3)
    rates = 1 + wander * rng.uniform(-1, 1, knots)
    rate = np.interp(np.linspace(0, knots - 1, STEPS), np.arange(knots), rates)
    return 2 * np.pi * cycles * np.cumsum(rate) / rate.sum()


def _finish(rng, shape: np.ndarray, noise: float, drift: float) -> np.ndarray:
    direction = rng.normal(size=3)
    trend = np.outer(np.linspace(0, 1, STEPS), direction / np.linalg.norm(direction)) * drift
    return _CENTRE + shape + trend + rng.normal(0, noise, (STEPS, 3))


def _interrupt(rng, shape: np.ndarray) -> np.ndarray:
    """``shape`` with the hand held still 1-4 times for 0.5-2 s each, from the row where it
    is farthest along a random direction (the ball's side), the movement resuming after."""
    out = shape.copy()
    direction = rng.normal(size=3)
    along = shape @ direction
    for _ in range(rng.integers(1, 5)):
        hold = int(round(rng.uniform(0.5, 2.0) / DT))
        start = int(rng.integers(0, STEPS - hold))
        # the nearest point of the path toward the ball at or after start
        window = along[start:min(start + 40, STEPS - hold)]
        if len(window) == 0:
            continue
        at = start + int(np.argmax(window))
        resumed = np.concatenate([out[:at], np.repeat(out[at:at + 1], hold, axis=0), out[at:]])
        out = resumed[:STEPS]
        along = out @ direction
    return out


def path(family: str, rng: np.random.Generator) -> Path:
    """One path of ``family`` (``FAMILIES``) drawn with ``rng``."""
    noise, drift = rng.uniform(0, 0.01), rng.uniform(0, 0.10)
    a, b = _plane(rng)
    if family in BABBLING_FAMILIES:
        radius = rng.uniform(0.06, 0.20)
        phi = _phase(rng, rng.uniform(5, 40), 0.15)
        if family.startswith("circle"):
            shape = radius * (np.outer(np.cos(phi), a)
                              + rng.uniform(0.5, 1.0) * np.outer(np.sin(phi), b))
        else:
            shape = radius * np.outer(np.sin(phi), a)
        if family.endswith("interrupted"):
            shape = _interrupt(rng, shape)
        return Path(family, True, _finish(rng, shape, noise, drift))
    if family == "rest":
        shape = np.zeros((STEPS, 3))
        drift = 0.0
    elif family == "reach and hold":
        t = np.clip(np.arange(STEPS) * DT / rng.uniform(1.0, 2.0), 0, 1)
        s = 10 * t ** 3 - 15 * t ** 4 + 6 * t ** 5  # minimum jerk
        shape = np.outer(s, a) * rng.uniform(0.1, 0.3)
    elif family == "drift":
        shape, drift = np.zeros((STEPS, 3)), rng.uniform(0.1, 0.3)
    elif family == "wander":
        raw = rng.normal(size=(STEPS + 40, 3))
        kernel = np.exp(-0.5 * (np.arange(-20, 21) / 6.0) ** 2)
        smooth = np.stack([np.convolve(raw[:, k], kernel, "same") for k in range(3)], 1)[20:-20]
        smooth -= smooth.mean(axis=0)
        shape = smooth * rng.uniform(0.06, 0.20) / np.sqrt((smooth ** 2).sum(1).mean())
    elif family == "small circles":
        phi = _phase(rng, rng.uniform(5, 40), 0.15)
        shape = rng.uniform(0.005, 0.03) * (np.outer(np.cos(phi), a) + np.outer(np.sin(phi), b))
        noise = min(noise, 0.003)
    elif family == "slow sweeps":
        phi = _phase(rng, rng.uniform(0.5, 2.0), 0.15)
        shape = rng.uniform(0.06, 0.20) * np.outer(np.sin(phi), a)
    else:
        raise ValueError(f"unknown family {family!r}; one of {FAMILIES}")
    return Path(family, False, _finish(rng, shape, noise, drift))


def labelled_set(per_family: int = 50, seed: int = 2026) -> list[Path]:
    """``per_family`` paths of every family, drawn from ``numpy.random.default_rng(seed)``."""
    rng = np.random.default_rng(seed)
    return [path(f, rng) for f in FAMILIES for _ in range(per_family)]
