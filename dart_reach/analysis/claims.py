"""The claims of the paper as data (sections IV and V, Table I): one :class:`Claim` per
statement the runs can test, with the paper's sentence and section, the measure, the groups,
the kind of claim (which rule of ``verdicts`` judges it) and the paper's level.

A claim whose statement is not the paper's, but the project's own reading, measure or
robustness check, has ``own=True``: it is judged like the others and counted apart from the
headline. A behaviour of Table I's "Resulting Behaviors" that the results (section IV) never
report of the robots has ``infants=True``: Table I schematizes the infants' phases the
training models (III-D: "three phases that model the three corresponding stages of the
development of reaching/grasping capabilities in infants ... (see Table I)"), and where
section IV cites the same sources for a robot result it is for another behaviour ([7] for
"more direct reaching movements", [30] for "the reduced mobility of the shoulder", [54] for
the improvement in grasping), never for reach onset, motor suppression or anticipatory grasp;
so those rows too are judged and counted apart. Where the
paper gives no number, the measure and threshold are the project's operationalisation, fixed
before any run was judged (docs/guides/analysis.md, "Claims").
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from .verdicts import ALPHA

#: "About half the trials" (IV-A-1): a reach rate between a third and two thirds.
ABOUT_HALF = (1 / 3, 2 / 3)
#: The trial-level babbling measure (docs/model/measures.md).
BABBLING = "babbling"
#: The measure of A1's babbling: babbling before the first touch, validated on the second
#: labelled sample with the ball and without it (docs/results/babbling-detector.md, which also
#: says where the third sample, on other robots, finds it short; the detector on the whole
#: trial is validated without the ball only there, and misses babbling that stops or changes
#: at the ball). Computed for a run's trials by running them again
#: (``postevaluation.before_touch``); a run without it has A1's babbling not run.
BABBLING_BOTH = "babbling_before_touch"
#: Why A3's babbling (no sight against normal senses) cannot be tested with the measures at
#: hand: none is validated in both of its conditions.
A3_BABBLING = ("no babbling measure is validated both with the ball (normal senses, the "
               "claim's reference) and without sight: the detector on the whole trial falls "
               "short with the ball on the second labelled sample, babbling before the touch "
               "without sight on the third (docs/results/babbling-detector.md)")
#: The measures that are a share of trials (a trial's boolean, a robot's mean over its trials):
#: a claim of no change in one is judged on the rate's own scale (``verdicts.RATE_MARGIN``).
RATES = ("babbling", BABBLING_BOTH, "reached", "grasped")
#: Swipes in the trials with a failed swipe (a swipe and no grasp; NaN in any other trial):
#: F2's "when they don't grasp the ball they try again" is conditional on a failed swipe
#: (``findings.robots`` derives it from ``swipes`` and ``grasped``).
SWIPES_AFTER_MISS = "swipes_after_miss"
#: Replications that need a trial with a failed swipe for F2 "swipes again" to be tested:
#: fewer, and it cannot be tested at this n (underpowered), not contradicted by trials in
#: which the robots never swiped (the absence of swipes is T11's, not counted twice).
SWIPES_AGAIN_UNITS = 6
#: "Try again with similar swipes": a swipe, then at least one more.
SWIPES_AGAIN = 2.0
#: The four sensory conditions of Fig. 9.
SENSES = ("normal", "no-touch", "no-sight", "nothing")


class Kind(enum.Enum):
    DIRECTIONAL = "directional"
    NOT_BETTER = "not better"
    NO_DIFFERENCE = "no difference"
    BAND = "band"
    EVERY_SECTOR = "every sector"
    AT_LEAST = "at least"
    NEVER = "never"
    PAIRED = "senses differ"
    SAME_PAIRED = "no change (paired)"
    CHANGE_PAIRED = "change (paired)"
    WITHIN = "measures of the same robots"


@dataclass(frozen=True)
class Claim:
    """One claim: ``measure`` of group ``b`` against group ``a`` (notations; "random pre" is the
    random pre-reaching networks of ``evaluate --baseline``), higher (``sign`` +1) or lower (-1)
    for a directional claim, "better" being higher (+1) or lower (-1) for a not-better claim;
    ``level`` the paper's significance level; ``unit`` "robots" (a robot's mean over its
    trials, judged on its replication's mean) or "replications" (the replication's best robot's
    post-evaluation fitness, Fig. 10); ``senses`` the sensory condition of the trials;
    ``versus`` a second sensory condition (the paired claims compare the same units under
    both; a directional claim compares the drop ``senses`` - ``versus``); ``versus_measure`` a
    second measure of the same units (``Kind.WITHIN``); ``source`` "post" or "development"
    (groups "phase@start" / "phase@end": the first / last tenth of the phase's generations).
    ``own``: the statement is the project's, not the paper's; ``infants``: the paper says it
    of infants (Table I), not of its robots; ``floor``: the least mean of an at-least claim;
    ``untestable``: why its measure cannot test it, whatever the data (by construction, or a
    measure not validated where the claim needs it; empty: it can): such a claim is never
    judged, and says so (``findings.UNTESTABLE``)."""

    id: str
    section: str
    paper: str
    kind: Kind
    measure: str = "fitness"
    a: str = ""
    b: str = ""
    sign: int = 0
    level: float = ALPHA
    unit: str = "robots"
    senses: str = "normal"
    versus: str = ""
    versus_measure: str = ""
    source: str = "post"
    own: bool = False
    infants: bool = False
    floor: float = float("nan")
    untestable: str = ""

    @property
    def effect_kind(self) -> Kind:
        """The kind whose effect the claim's findings row carries: a development claim of
        one phase at two moments is judged on the same replications, paired (a change, not
        theta), whatever its ``kind``."""
        if (self.source == "development" and self.kind is Kind.DIRECTIONAL
                and self.a.split("@")[0] == self.b.split("@")[0]):
            return Kind.CHANGE_PAIRED
        return self.kind


_K = Kind


def _phase_claims() -> list[Claim]:
    claims = [
        Claim("F1 reach about half", "IV-A-1, Fig. 5",
              "pre-reachers reach (touch the ball at least once) in about half of the trials",
              _K.BAND, "reached", b="pre"),
        Claim("F1 babbling", "IV-A-1, Fig. 8",
              "pre-reachers show \"large quasi-periodic circular movements\" of the hand "
              "(motor babbling), unlike random networks", _K.DIRECTIONAL, BABBLING,
              "random pre", "pre", +1),
        Claim("F1 arm extended", "IV-A-1, Fig. 8", "pre-reachers' movements are \"produced "
              "with the arm extended\": the hand farther from the shoulder than random "
              "networks'", _K.DIRECTIONAL, "hand_shoulder_mean", "random pre", "pre", +1),
        Claim("F1 hand-shoulder constant vs random", "IV-A-1, Fig. 6 top",
              "\"the distance between the shoulder and the hand remains almost constant\"",
              _K.DIRECTIONAL, "hand_shoulder_cv", "random pre", "pre", -1),
        Claim("F1 hand-shoulder constant vs fine", "IV-A-1, IV-A-3, Fig. 6",
              "the elbow, locked in pre-reaching, is used in fine-reaching", _K.DIRECTIONAL,
              "hand_shoulder_cv", "fine", "pre", -1),
    ]
    for other in ("shoulder", "trunk"):
        claims.append(Claim(
            f"F1 elbow locked: elbow < {other}", "IV-A-1, Fig. 6 bottom",
            "\"a large use of the DOFs of the trunk and of the shoulder and a limited use "
            "(locking) of the DOF of the elbow\" (variability normalised by the joints' range)",
            _K.WITHIN, "var_elbow_norm", b="pre", sign=-1, versus_measure=f"var_{other}_norm"))
    for measure, sign, level, what in (
            ("grasped", +1, 0.001, "grasp up"), ("reached", -1, 0.001, "reach down"),
            ("straightness", +1, 0.01, "straighter"), ("speed", -1, 0.05, "slower"),
            ("var_shoulder", -1, 0.001, "shoulder variability down"),
            ("sectors_reached", -1, ALPHA, "success in fewer sectors")):
        claims.append(Claim(f"F2 {what}", "IV-A-2, Figs. 5-7",
                            f"gross- vs pre-reachers: {what}", _K.DIRECTIONAL, measure, "pre",
                            "gross", sign, level))
    claims.append(Claim("F2 swipes again", "IV-A-2", "\"The visual inspection of the best "
                        "robots at the end of this phase reveals that they ... produce long "
                        "swipes up. When they don't grasp the ball they try again with similar "
                        "swipes\": in a gross-reacher's trial with a failed swipe (a swipe and no "
                        "grasp), another (at least 2 swipes on average)", _K.AT_LEAST,
                        SWIPES_AFTER_MISS,
                        b="gross", floor=SWIPES_AGAIN))
    claims.append(Claim("F2 swipes: gross > pre", "IV-A-2 (the project's reading)",
                        "gross-reachers swipe more per trial than pre-reachers",
                        _K.DIRECTIONAL, "swipes", "pre", "gross", +1, own=True))
    for measure, sign, level, what in (
            ("reached", +1, 0.001, "reach up"), ("grasped", +1, 0.001, "grasp up"),
            ("var_elbow", +1, 0.001, "elbow variability up"),
            ("var_shoulder", +1, 0.001, "shoulder variability up"),
            ("var_trunk", +1, 0.001, "trunk variability up")):
        claims.append(Claim(f"F3 {what}", "IV-A-3, Figs. 5, 6",
                            f"fine- vs gross-reachers: {what}", _K.DIRECTIONAL, measure,
                            "gross", "fine", sign, level))
    for measure, better in (("speed", -1), ("straightness", +1)):
        claims.append(Claim(f"F3 {measure} not better", "IV-A-3, Fig. 5",
                            "\"The analysis of speed and straightness in reaching, instead, "
                            "does not indicate any significant improvement during this phase\""
                            + (" (better speed is slower: IV-A-2 counts gross's \"decrease of "
                               "movement speed\" among its \"more direct\" reaches)"
                               if measure == "speed" else ""),
                            _K.NOT_BETTER, measure, "gross", "fine", better))
    claims.append(Claim("F3 all sectors", "IV-A-3, Fig. 7",
                        "fine-reachers \"acquire a capacity to successfully accomplish these "
                        "actions in all areas\"", _K.EVERY_SECTOR, b="fine"))
    claims.append(Claim("F3 elbow un-freezes later", "V", "\"the reduced use (freeze) "
                        "followed by a re-extended use (un-freeze) of the distal DOFs\": the "
                        "elbow of fine-reachers moves more than pre-reachers'", _K.DIRECTIONAL,
                        "var_elbow_norm", "pre", "fine", +1))
    for phase in ("pre", "gross", "fine"):
        claims.append(Claim(f"F4 senses differ ({phase})", "IV-B, Fig. 9",
                            "\"performance significantly varies\" across the four sensory "
                            "conditions (p < 0.01)", _K.PAIRED, b=phase, level=0.01))
    for s in SENSES:
        pairs = ((("gross", "fine", +1, "fine > gross"), ("pre", "gross", +1, "gross > pre"))
                 if s in ("normal", "no-touch") else (("gross", "fine", -1, "gross > fine"),))
        for a, b, sign, what in pairs:
            claims.append(Claim(f"F4 {s}: {what}", "IV-B, Fig. 9", f"{s}: {what} (p < 0.05)",
                                _K.DIRECTIONAL, "fitness", a, b, sign, 0.05, senses=s))
    claims.append(Claim("F5 gross > gross^", "IV-C, Fig. 10",
                        "\"the gross condition significantly outperforms the non-incremental "
                        "gross^ condition (p < 0.05, two tailed Mann-Whitney U test)\"",
                        _K.DIRECTIONAL, "fitness", "gross^", "gross", +1, 0.05,
                        "replications"))
    claims.append(Claim("F5 gross > gross^ (best 5)", "IV-C, Fig. 10 (the project's reading)",
                        "the same, each replication's unit the mean of its best 5 robots' "
                        "post-evaluation fitness (Figs. 5-7's robots) instead of its best "
                        "robot's", _K.DIRECTIONAL, "fitness", "gross^", "gross", +1, 0.05,
                        own=True))
    for standard, control in (("pre", "pre-h"), ("gross", "gross-h"), ("pre", "pre*"),
                              ("gross^", "gross^*"), ("fine^", "fine*"), ("fine", "fine^")):
        claims.append(Claim(f"F6 {standard} not better than {control}", "IV-C, Fig. 10",
                            "\"the standard experimental conditions do not lead to "
                            f"significantly better performance\": {standard} vs {control}",
                            _K.NOT_BETTER, "fitness", control, standard, +1,
                            unit="replications"))
    for g in ("fine*", "fine^"):
        claims.append(Claim(f"F7 {g} never babbles", "IV-C",
                            "\"the robots trained in the fine* and fine^ experimental "
                            "conditions never display such behavior\" (read: they babble less "
                            "than pre-reachers)", _K.NEVER, BABBLING, "pre", g, -1))
    claims.append(Claim("F7 gross^ never babbles", "IV-C (the project's reading)",
                        "gross^ (internal neurons from the start) babbles less than "
                        "pre-reachers", _K.NEVER, BABBLING, "pre", "gross^", -1, own=True))
    return claims


def _behaviour_claims() -> list[Claim]:
    fig8, dep, tab, ctl, dev = ("IV-A-1, Fig. 8: ball absent", "IV-B, V: deprivation",
                                "Table I, IV-A: behaviours", "IV-C: controls",
                                "V, IV-C: development")
    c = [Claim(f"A1 ball absent, pre: {m} same", fig8,
               "pre-reachers: \"the behavior of the robot remains substantially the same "
               "during post-evaluation tests in which the target ball is absent\""
               + (" (babbling before the first touch, the measure validated with and "
                  "without the ball on the second labelled sample)" if m == BABBLING else ""),
               _K.SAME_PAIRED, BABBLING_BOTH if m == BABBLING else m, b="pre",
               versus="no-ball")
         for m in ("babbling", "hand_amplitude", "hand_path", "var_shoulder")]
    c += [Claim(f"A2 ball absent, fine: {m} down", fig8,
                "fine-reachers, who rely on sight (IV-B), move differently without the ball",
                _K.CHANGE_PAIRED, m, b="fine", sign=-1, versus="no-ball", own=True)
          for m in ("heading", "hand_path")]
    c.append(Claim("A2 ball absent: fine's heading drop > pre's", fig8,
                   "the ball's absence changes fine-reachers more than pre-reachers",
                   _K.DIRECTIONAL, "heading", "pre", "fine", +1, versus="no-ball", own=True))
    c += [Claim(f"A3 no sight, pre: {m} same", fig8,
                "pre-reachers: the behaviour remains the same \"in tests in which the vision "
                "system is impaired\"", _K.SAME_PAIRED, m, b="pre", versus="no-sight",
                untestable=A3_BABBLING if m == BABBLING else "")
          for m in ("babbling", "hand_amplitude", "hand_path")]
    for a in ("gross", "pre"):
        c.append(Claim(f"D1 no-sight drop: fine > {a}", dep,
                       "\"the most notable effect is the strong impairment caused by the "
                       "absence of visual information in the fine-reaching phase\"",
                       _K.DIRECTIONAL, "fitness", a, "fine", +1, versus="no-sight"))
    # the no-touch condition silences the palm's touch sensor, which is also the input of the
    # hand-coded grasp reflex: fitness (Eq. 5 rewards grasping) would drop even for a network
    # that ignores touch; and the reach, a first touch, cannot differ: before it every touch
    # sensor is silent under normal senses too, so a trial runs the same up to it
    c.append(Claim("D2 no touch, pre: reach same", dep, "pre-reachers ignore tactile "
                   "information (V): their reach rate is the same without touch (not their "
                   "fitness: without the palm's touch the grasp reflex is silent too)",
                   _K.SAME_PAIRED, "reached", b="pre", versus="no-touch",
                   untestable="a trial reaches (touches the ball) under no touch exactly when "
                   "it does under normal senses, since every touch sensor is silent until the "
                   "first touch: the same by construction"))
    for g in ("gross", "fine"):
        c.append(Claim(f"D3 no touch, {g}: fitness down", dep, "\"the utilization of tactile "
                       "information becomes a necessary prerequisite\" after pre-reaching (V)",
                       _K.CHANGE_PAIRED, "fitness", b=g, sign=-1, versus="no-touch"))
    c.append(Claim("D3 no-touch drop: gross > pre", dep, "touch matters more to gross- than "
                   "to pre-reachers (V)", _K.DIRECTIONAL, "fitness", "pre", "gross", +1,
                   versus="no-touch"))
    c.append(Claim("T1 arm orienting", tab, "pre-reaching: \"arm orienting\" [49]: the hand "
                   "heads toward the ball more than random networks'", _K.DIRECTIONAL,
                   "heading", "random pre", "pre", +1))
    c.append(Claim("T2 reach onset", tab, "gross-reaching: \"reach onset\" [7] (of infants; "
                   "the text does not say it of the robots): the first touch comes sooner than "
                   "pre-reachers'", _K.DIRECTIONAL, "first_touch_s", "pre", "gross", -1,
                   infants=True))
    for g in ("gross", "fine"):
        c.append(Claim(f"T4 babbling reduced in {g}", tab, "\"the reduced use of motor "
                       "babbling\" after pre-reaching (III-D-2, V)", _K.DIRECTIONAL,
                       BABBLING, "pre", g, -1))
    c.append(Claim("T6 anticipatory grasp", tab, "fine-reaching: \"anticipatory grasp\" "
                   "[54] (of infants; the text does not say it of the robots): fingers closing "
                   "before the palm touches", _K.DIRECTIONAL, "anticipatory_grasp", "gross",
                   "fine", +1, infants=True))
    c.append(Claim("T7 smoother reach (infants)", tab, "fine-reaching: \"smoother and "
                   "straighter reach\" [27], [12], [26], of infants: fewer movement units than "
                   "gross-reachers", _K.DIRECTIONAL, "movement_units", "gross", "fine", -1,
                   infants=True))
    c.append(Claim("T7 smoothness not better", "IV-A-3 (the project's measure)", "fine-reachers "
                   "improve as infants do, \"who however also show a significant improvement "
                   "in smoothness and straightness [12], [27] during this phase\": the paper "
                   "never measures the robots' smoothness (its robot claim is F3's speed and "
                   "straightness); the project's reading: the robots' reach is not "
                   "significantly smoother (movement units not fewer) than gross-reachers'",
                   _K.NOT_BETTER, "movement_units", "gross", "fine", -1, own=True))
    for m, sign, level in (("straightness_onset", +1, 0.01), ("speed_final", -1, 0.05),
                           ("speed_peak", -1, 0.05)):
        c.append(Claim(f"T8 gross vs pre: {m}", tab, "robustness of F2 straighter / slower "
                       "with the reach from movement onset", _K.DIRECTIONAL, m, "pre", "gross",
                       sign, level, own=True))
    for m, better in (("straightness_onset", +1), ("speed_final", -1), ("speed_peak", -1)):
        c.append(Claim(f"T9 fine vs gross: {m} not better", tab, "robustness of F3's \"no "
                       "significant improvement\"", _K.NOT_BETTER, m, "gross", "fine", better,
                       own=True))
    for m, a, b, sign in (("var_shoulder_before", "pre", "gross", -1),
                          ("var_shoulder_norm", "pre", "gross", -1),
                          ("var_elbow_before", "gross", "fine", +1),
                          ("var_elbow_norm", "gross", "fine", +1)):
        c.append(Claim(f"T10 {b} vs {a}: {m}", tab, "robustness of F2/F3's joint "
                       "variability: before the first touch, normalised by the joint's range",
                       _K.DIRECTIONAL, m, a, b, sign, 0.001, own=True))
    for a in ("pre", "fine"):
        c.append(Claim(f"T11 palm-up swipes: gross > {a}", tab, "gross-reachers \"bring their "
                       "arm on the lower part of the target area while orienting their palm up "
                       "and then produce long swipes up\" (IV-A-2)", _K.DIRECTIONAL,
                       "palm_up_swipe", a, "gross", +1))
    c.append(Claim("P1 peri-personal space shrinks in gross", tab, "the regression \"involves "
                   "a reduction of the peri-personal space\" (V)", _K.DIRECTIONAL,
                   "reach_entropy", "pre", "gross", -1))
    c.append(Claim("P2 and re-expands in fine", tab, "fine-reachers succeed \"in all areas\" "
                   "(IV-A-3)", _K.DIRECTIONAL, "reach_entropy", "gross", "fine", +1))
    for a, b, what in (("pre", "pre-h", "the reduced visual acuity"),
                       ("pre", "pre*", "the lack of reflexes"),
                       ("gross^", "gross^*", "the lack of reflexes"),
                       ("fine^", "fine*", "the lack of reflexes")):
        for m in ("babbling", "hand_amplitude", "heading", "hand_shoulder_cv"):
            c.append(Claim(f"C {a} vs {b}: {m} same", ctl, f"{what} \"does not lead to an "
                           "appreciable effect on the observed behavior\" / \"does not alter "
                           "significantly the type of behavior\"", _K.NO_DIFFERENCE, m, a, b))
    c += [Claim("V1 motor suppression at the start of gross", dev, "\"initial motor "
                "suppression\" [30] (Table I, of infants; the text does not say it of the "
                "robots): less movement in gross's first tenth of generations than in pre's "
                "last", _K.DIRECTIONAL, "hand_path", "pre@end", "gross@start", -1,
                source="development", infants=True),
          Claim("V2 elbow un-freezes in fine", dev, "\"the reduced use (freeze) followed by a "
                "re-extended use (un-freeze) of the distal DOFs\"", _K.DIRECTIONAL,
                "var_elbow", "fine@start", "fine@end", +1, source="development"),
          Claim("V3 babbling appears in pre", dev, "\"the emergence of the exploratory (motor "
                "babbling) behavior during the pre-reaching phase\"", _K.DIRECTIONAL,
                BABBLING, "pre@start", "pre@end", +1, source="development"),
          Claim("V4 babbling fades in gross", dev, "\"this transient behavior is later "
                "replaced by more effective movements\"", _K.DIRECTIONAL, BABBLING,
                "gross@start", "gross@end", -1, source="development")]
    c += [Claim(f"V5 {g} never babbles during development", dev, f"{g} robots \"never display "
                "such behavior during the course of their developmental process\" (read: "
                "their highest babbling over the snapshots is below pre-reachers')", _K.NEVER,
                BABBLING, "pre", g, -1, source="development") for g in ("fine*", "fine^")]
    return c


CLAIMS: tuple[Claim, ...] = tuple(_phase_claims() + _behaviour_claims())
