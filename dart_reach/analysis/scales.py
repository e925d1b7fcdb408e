"""What a claim's effect is, in which units, and how the forest of the report draws it
(``budgets.toward_paper``: a scale on which the paper's direction is right): one entry per kind
of claim (``claims.Kind``), said once for the report's captions and its answers.

``inverted(claim)`` says, for a claim whose label reads against the axis (a claim of "not
better", a claim that the paper's direction is *lower*), what the label means on the figure.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import verdicts
from .claims import ABOUT_HALF, CLAIMS, Claim, Kind


@dataclass(frozen=True)
class Scale:
    """A kind of claim's effect: ``symbol`` (a few characters, before its value), ``effect``
    (what it is, with its units) and ``drawn`` (what the forest draws, 0 and the right side
    explained)."""

    symbol: str
    effect: str
    drawn: str


_THETA = "θ = P(b > a) + P(b = a) / 2 of two replications drawn one from each group " \
         "(a probability, no units; 0.5: no difference)"
_M = verdicts.EQUIVALENCE_MARGIN
SCALES: dict[str, Scale] = {
    Kind.DIRECTIONAL.value: Scale("θ", _THETA, "sign × (θ − 0.5): 0 is no difference, right "
                                               "is the paper's direction"),
    Kind.NEVER.value: Scale("θ", _THETA, "sign × (θ − 0.5): 0 is no difference, right is "
                                         "less babbling than pre-reachers"),
    Kind.NOT_BETTER.value: Scale(
        "θ(better)", "θ(better) = P(b better than a) (a probability; 0.5: neither better)",
        f"{0.5 + _M:g} − θ(better): 0 is the margin, right is \"not better\""),
    Kind.NO_DIFFERENCE.value: Scale(
        "θ", _THETA, f"{_M:g} − |θ − 0.5|: 0 is the margin, right is \"no difference\""),
    Kind.BAND.value: Scale(
        "mean", "mean reach rate over replications (a share of trials, 0 to 1)",
        f"the distance inside the band [{ABOUT_HALF[0]:.2g}, {ABOUT_HALF[1]:.2g}]: right of 0 "
        "is inside"),
    Kind.EVERY_SECTOR.value: Scale(
        "weakest", "the weakest sector's reach or grasp rate (a share of trials, 0 to 1)",
        f"that rate − {verdicts.SECTOR_FLOOR:g} (the floor): right of 0 is above it"),
    Kind.AT_LEAST.value: Scale(
        "mean", "the mean over replications, in the measure's units",
        "that mean − the claim's floor: right of 0 is above it"),
    Kind.PAIRED.value: Scale(
        "W", "Kendall's W across the four sensory conditions (0: no agreement, 1: every "
             "replication ranks them alike; no units)",
        "W itself, without an interval: in the column \"no interval\""),
    Kind.SAME_PAIRED.value: Scale(
        "change", "the mean change between the two conditions (rate units for a rate, else "
                  "relative to each replication's level)",
        "−|change|: 0 is no change, every change is left of it"),
    Kind.CHANGE_PAIRED.value: Scale(
        "change", "the Hodges-Lehmann change between the two conditions, in the measure's "
                  "units", "sign × change: 0 is no change, right is the paper's direction"),
    Kind.WITHIN.value: Scale(
        "change", "the Hodges-Lehmann difference of the two measures of the same "
                  "replications, in the measures' units",
        "sign × difference: 0 is none, right is the paper's direction"),
}

_BY_ID = {c.id: c for c in CLAIMS}


def scale(kind: str) -> Scale:
    """The scale of a kind of claim (``Kind.value``)."""
    try:
        return SCALES[kind]
    except KeyError:
        raise ValueError(f"unknown kind of claim {kind!r}; known: {list(SCALES)}") from None


def scale_of(claim: str, kind: str) -> Scale:
    """The scale of a findings row: its claim's ``Claim.effect_kind`` (a paired development
    claim carries a change), else its ``kind``."""
    c = _BY_ID.get(claim)
    return scale(c.effect_kind.value if c is not None else kind)


def inverted(claim: Claim | str) -> str:
    """What a label that reads against the axis means ("" for one that does not): a claim of
    "not better", where better may be lower, and a claim whose direction is lower."""
    c = _BY_ID[claim] if isinstance(claim, str) else claim
    if c.kind is Kind.NOT_BETTER:
        word = "lower" if c.sign < 0 else "higher"
        return (f"better means a {word} {c.measure}: the claim holds (right of 0) when {c.b} "
                f"is not more often {word} than {c.a} beyond the margin, "
                f"θ(better) < {0.5 + _M:g}; left: {c.b} is {word}")
    if c.sign < 0 and c.kind in (Kind.DIRECTIONAL, Kind.NEVER, Kind.CHANGE_PAIRED,
                                 Kind.WITHIN):
        what = (f"{c.b}'s {c.measure} is lower than {c.versus_measure}" if c.kind is Kind.WITHIN
                else f"{c.measure} falls under {c.versus}" if c.kind is Kind.CHANGE_PAIRED
                else f"{c.measure} falls from {c.a} to {c.b}" if c.source == "development"
                else f"{c.b}'s {c.measure} is lower than {c.a}'s")
        return f"the paper's direction is lower: drawn right of 0 when {what}"
    return ""


#: The ids of the claims ``inverted`` knows (``claims.CLAIMS``).
CLAIM_IDS = frozenset(_BY_ID)
