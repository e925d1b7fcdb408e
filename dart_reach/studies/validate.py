"""Model checks a user can rerun (``dart-reach validate``): is the task the paper's and can it
be learned? Each check measures the shipped world (paper sections II-D, III, III-A-D, Figs. 1-4)
and returns plain numbers; ``run`` gathers them with their pass/fail verdicts.

- ``scene``: on a dense grid of every sector (corners included), at the home posture: the ball
  in the 112 x 94 deg field of view, its distance from the eyes within the 50 cm of the
  distance sensor (Eq. 3), its clearance from every robot body and from the palm, and a
  posture of the arm within the joint limits that puts the palm on it.
- ``self_collision_pairs``: with self-collision on, which arm-body pairs meet in random
  postures (a measurement for ``WorldConfig.self_collision``, not one of ``run``'s checks).
- ``scripted_grasps``: a scripted reach-and-grasp meets the paper's grasp definition (palm and
  a finger on the ball at once, on their inner faces) at the 45 post-evaluation points.
- ``reflex_rates``: in a random pre-reaching population, how often the orienting reflex brings
  the ball's image toward the centre within 3 s and how often a touch on the palm closes the
  hand, with and without the reflexes.
- ``chance``: the post-evaluation of random networks (the baseline of every measure).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import dartpy as dart
import numpy as np

from ..analysis.stats import bootstrap_mean_interval
from ..evolution.genome import ParamGroup, decode, random_genome
from ..evolution.settings import standard_trial
from ..measures.metrics import grasped, trial_metrics
from ..model.kernels.sensing import project
from ..model.ctrnn import MOTOR_INDEX, SENSOR_INDEX, motor_targets
from ..model.levers import ReflexInputs
from ..model.scripted import ScriptedReach, grasp_posture
from ..model.servo import Servo
from ..model.task import Trial, network_for, trial_positions
from ..model.world import N_SECTORS, World

#: Seconds within which the orienting reflex must bring the ball's image toward the centre.
ORIENT_SECONDS = 3.0
#: Control steps the palm is touched before the hand's target is read (0.5 s).
GRASP_STEPS = 5
#: Random networks of the reflex checks. About half have the ball in view to judge the head's
#: turn (docs/model/levers.md, "What drives the reflex motors", gives the counts), so 200 give
#: a rate's standard error of at most 0.05 (sqrt(0.25 / 100)); a few dozen networks left the
#: rates too close to the checks' thresholds to decide.
REFLEX_NETWORKS = 200
#: Random networks of the chance check (1,350 trials). The unit is the network: one in
#: six may reach in nearly every trial, so six networks could not decide "fewer than half".
CHANCE_NETWORKS = 30


# ------------------------------------------------------------------------------------- scene
def _collision_shapes(world: World):
    return [s for b in world.robot.getBodyNodes() for s in b.getShapeNodes()
            if s.getCollisionAspect() is not None]


def _surface_distance(shape, point: np.ndarray) -> float:
    """Distance (m) from ``point`` to a box or sphere collision shape (negative inside a
    sphere, 0 inside a box)."""
    T = shape.getWorldTransform()
    local = T.rotation().T @ (point - T.translation())
    geometry = shape.getShape()
    if isinstance(geometry, dart.dynamics.BoxShape):
        half = np.asarray(geometry.getSize()) / 2
        return float(np.linalg.norm(np.maximum(np.abs(local) - half, 0.0)))
    return float(np.linalg.norm(local) - geometry.getRadius())


def arm_length(world: World) -> float:
    """Length (m) of the right arm, from the shoulder (``icub.SHOULDER``) to the palm centre with
    the elbow straight and every other joint at home: the unit of the scene's distances."""
    robot = world.robot
    q = world.home.copy()
    elbow = robot.getJoint("r_elbow").getIndexInSkeleton(0)
    q[elbow] = world.lower[elbow]
    robot.setPositions(q)
    length = float(np.linalg.norm(world.hand_position() - world.shoulder_position()))
    robot.setPositions(world.home)
    return length


def scene_geometry(world: World, grid: int = 7) -> dict:
    """Where the ball's start positions lie relative to the robot's right arm at home (the
    quantities the infant experiments set: docs/model/scene.md), over a ``grid`` x
    ``grid`` lattice of every sector: the ball centre's distance from the shoulder as a fraction
    of the arm's length, its elevation seen from the shoulder (deg, + up) and its lateral offset
    from the body's midline (m, + toward the right arm); min, median and max of each."""
    robot = world.robot
    robot.setPositions(world.home)
    fractions = np.linspace(0.0, 1.0, grid)
    points = np.array([world.sector_point(k, u, v) for k in range(N_SECTORS)
                       for u in fractions for v in fractions])
    d = points - world.shoulder_position()
    arm = arm_length(world)
    out = {"arm_length_m": arm}
    for key, values in (("arm_fraction", np.linalg.norm(d, axis=1) / arm),
                        ("elevation", np.degrees(np.arctan2(d[:, 2], np.hypot(d[:, 0],
                                                                              d[:, 1])))),
                        ("lateral", points[:, 1])):
        unit = {"elevation": "_deg", "lateral": "_m"}.get(key, "")
        out.update({f"{key}_{stat}{unit}": float(f(values))
                    for stat, f in (("min", np.min), ("median", np.median), ("max", np.max))})
    return out


def scene(world: World, grid: int = 7) -> dict:
    """Start positions on a ``grid`` x ``grid`` lattice of every sector (its corners included)
    checked at the home posture. Returns fractions and extremes over all of them."""
    robot = world.robot
    robot.setPositions(world.home)
    cam = world.camera_pose()
    R, origin = cam[:3, :3], cam[:3, 3]
    palm = world.hand_position()
    shapes = _collision_shapes(world)
    radius = world.config.ball.radius
    in_view, distance, clearance, palm_gap, reach_error = [], [], [], [], []
    fractions = np.linspace(0.0, 1.0, grid)
    for sector in range(N_SECTORS):
        for u in fractions:
            for v in fractions:
                p = world.sector_point(sector, u, v)
                p_cam = (p - origin) @ R
                in_view.append(project(*p_cam.tolist())[2])
                distance.append(float(np.linalg.norm(p_cam)))
                clearance.append(min(_surface_distance(s, p) for s in shapes) - radius)
                palm_gap.append(float(np.linalg.norm(p - palm)) - radius)
                reach_error.append(grasp_posture(world, p).palm_error)
    robot.setPositions(world.home)
    return {
        "positions": len(in_view),
        "in_view_fraction": float(np.mean(in_view)),
        "eye_distance_min_m": min(distance),
        "eye_distance_max_m": max(distance),
        "clearance_min_m": min(clearance),
        "palm_gap_min_m": min(palm_gap),
        "reach_error_max_m": max(reach_error),
    }


def self_collision_pairs(world: World, postures: int = 2000, seed: int = 0) -> dict:
    """Which arm-body pairs meet in ``postures`` random postures, every joint uniform within its
    limits, in a world with self-collision on (``WorldConfig.self_collision``: the arm against
    the body, ``World._collide_arm_with_body``'s filter). Returns the share of postures where
    any pair meets and, per pair of body names, the number of postures where it meets; the
    robot is left at home. Raises ValueError if the world's self-collision is off."""
    if not world.config.self_collision:
        raise ValueError("self_collision_pairs needs a world with self-collision on")
    robot = world.robot
    solver = world.world.getConstraintSolver()
    option = dart.collision.CollisionOption()
    option.maxNumContacts = 1000
    option.collisionFilter = solver.getCollisionOption().collisionFilter
    group = solver.getCollisionDetector().createCollisionGroup()
    group.addShapeFramesOf(robot)
    low, high = robot.getPositionLowerLimits(), robot.getPositionUpperLimits()
    rng = np.random.default_rng(seed)
    pairs: dict[tuple[str, str], int] = {}
    met = 0
    for _ in range(postures):
        robot.setPositions(rng.uniform(low, high))
        result = dart.collision.CollisionResult()
        group.collide(option, result)
        names = set()
        for i in range(result.getNumContacts()):
            contact = result.getContact(i)
            names.add(tuple(sorted(o.getShapeFrame().getBodyNodePtr().getName()
                                   for o in (contact.collisionObject1, contact.collisionObject2))))
        met += bool(names)
        for pair in names:
            pairs[pair] = pairs.get(pair, 0) + 1
    robot.setPositions(world.home)
    return {"postures": postures, "met_share": met / postures, "pairs": pairs}


# ----------------------------------------------------------------------------- scripted grasp
def scripted_grasps(world: World, seconds: float = 10.0, points=None) -> dict:
    """The scripted reach-and-grasp at the 45 post-evaluation points (or at ``points``, ball
    positions of shape (n, 3)): how many grasps (the paper's definition, ``metrics.grasped``)
    and the hand's peak speed (m/s, the median over the points). The world is stepped by the
    living model's servo (``servo.Servo``)."""
    steps = round(seconds / world.config.control_dt)
    grasps, peak = 0, []
    servo = Servo(world)
    for point in world.systematic_points() if points is None else np.asarray(points, float):
        servo.reset(point)
        reach = ScriptedReach(world, point)
        contacts = np.zeros((steps, len(world.layout.segment_body)), bool)
        hand = np.zeros((steps, 3))
        for t in range(steps):
            world.hand_contacts(contacts[t])
            hand[t] = world.hand_position()
            servo.step(reach.targets(contacts[t]))
        grasps += grasped(contacts)
        peak.append(_peak_speed(hand, world.config.control_dt))
    return {"scripted_grasps": int(grasps), "scripted_points": len(peak),
            "scripted_peak_hand_speed_m_s": float(np.median(peak))}


def _peak_speed(hand: np.ndarray, dt: float) -> float:
    return float(np.linalg.norm(np.diff(hand, axis=0), axis=1).max() / dt)


# ----------------------------------------------------------------------------------- reflexes
def reflex_rates(world: World, reflexes: bool, networks: int = REFLEX_NETWORKS, seed: int = 0,
                 reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET) -> dict:
    """A random pre-reaching population (``networks`` random genomes: direct connections only,
    low acuity a = 3) with or without the reflexes (pre vs pre*, section IV-C).

    Each network runs a trial of ``ORIENT_SECONDS`` with the ball at a random point of a random
    sector. ``head_turn_rate``: the fraction of networks whose neck, at the end, holds the ball's
    image closer to the centre than the home neck angles would with the body where it is (the
    head turned toward the ball), among the ``head_turn_judged`` networks whose trunk left the
    ball in view with one neck posture or the other. ``image_closer_rate``: the fraction whose
    ball image is closer
    to the centre at the end than at the start (p_sight grew; out of view counts as far): this
    counts the trunk's motion too.
    ``grasp_rate_touched`` / ``grasp_rate_untouched``: from the state each network reached at
    the end of that trial, its palm touch sensor is held at touched (+1) or untouched (-1) for
    ``GRASP_STEPS`` control steps, the rest of its input as it was; the fraction of networks
    whose hand target is then past half-closed (> 0). A reflex acts when the touched rate is a
    clear majority and well above the untouched rate. ``reflex_inputs``: the lever of what
    else drives the reflex motors (``levers.ReflexInputs``).
    """
    config = standard_trial("pre", reflexes=reflexes, trials=1, reflex_inputs=reflex_inputs,
                            steps=round(ORIENT_SECONDS / world.config.control_dt) + 1)
    trial = Trial(world, config)
    rng = np.random.default_rng(seed)
    image_closer, head_turned, judged, closed = 0, 0, 0, {1.0: 0, -1.0: 0}
    palm, hand = SENSOR_INDEX["touch/palm"], MOTOR_INDEX["r_hand_fingers"]
    for genome in random_genome(rng, networks):
        network = network_for(decode(genome, {ParamGroup.DIRECT}), config)
        (sector, position), = trial_positions(world, rng, 1)
        data = trial.run(network, sector, position)
        image_closer += bool(data.p_sight[-1] > data.p_sight[0])
        turned = _neck_centres_ball(world, data.dofs[-1], data.ball[-1])
        if turned is not None:
            judged += 1
            head_turned += turned
        state = network.motor.copy()
        for touch in closed:
            network.motor[:] = state
            x = data.sensors[-1].copy()
            x[palm] = touch
            for _ in range(GRASP_STEPS):
                network.step(x)
            closed[touch] += bool(motor_targets(network.motor)[hand] > 0.0)
    return {"head_turn_rate": head_turned / max(judged, 1), "head_turn_judged": judged,
            "image_closer_rate": image_closer / networks,
            "grasp_rate_touched": closed[1.0] / networks,
            "grasp_rate_untouched": closed[-1.0] / networks}


def _image_offset(world: World, q: np.ndarray, ball: np.ndarray) -> float:
    """|c| of the ball's image with the robot at joint positions ``q`` (inf out of view)."""
    world.robot.setPositions(q)
    cam = world.camera_pose()
    cx, cy, in_view = project(*((ball - cam[:3, 3]) @ cam[:3, :3]).tolist())
    return math.hypot(cx, cy) if in_view else math.inf


def _neck_centres_ball(world: World, q: np.ndarray, ball: np.ndarray) -> bool | None:
    """Did the neck's own motion bring the ball's image closer to the centre? |c| with the
    neck where it is against |c| with the neck at home and the rest of the body where it is
    (the trunk moves the head too; that is not the orienting response). None when the ball is
    out of view with the neck either way."""
    saved = world.robot.getPositions()
    neck = world.layout.motor_dofs[:3]
    at_home = q.copy()
    at_home[neck] = world.home[neck]
    now, home = _image_offset(world, q, ball), _image_offset(world, at_home, ball)
    world.robot.setPositions(saved)
    if math.isinf(now) and math.isinf(home):
        return None  # out of view either way: the reflex has nothing to orient to
    return now < home


# ------------------------------------------------------------------------------------- chance
def chance(world: World, networks: int = CHANCE_NETWORKS, seed: int = 1) -> dict:
    """Random pre-reaching networks (reflexes on, low acuity) post-evaluated on the 45
    systematic positions: mean fitness, reach and grasp rates (the chance level of Fig. 5),
    each network's reach rate, the reach rate's 95 % bootstrap interval over networks (the
    unit: one network may reach in nearly every trial and the next in none) and the median
    of their trials' peak hand speeds (m/s)."""
    config = standard_trial("pre")
    trial = Trial(world, config)
    rng = np.random.default_rng(seed)
    rows, peaks, per_network = [], [], []
    for genome in random_genome(rng, networks):
        network = network_for(decode(genome, {ParamGroup.DIRECT}), config)
        reached = []
        for k, point in enumerate(world.systematic_points()):
            data = trial.run(network, k // 5, point)
            rows.append(trial_metrics(data, world.config.control_dt))
            reached.append(rows[-1]["reached"])
            peaks.append(_peak_speed(data.hand[:data.steps_run], world.config.control_dt))
        per_network.append(float(np.mean(reached)))
    _, low, high = bootstrap_mean_interval(per_network, rng)
    return {"random_networks": networks,
            "random_fitness": float(np.mean([r["fitness"] for r in rows])),
            "random_reach_rate": float(np.mean([r["reached"] for r in rows])),
            "random_reach_per_network": per_network,
            "random_reach_rate_low": low, "random_reach_rate_high": high,
            "random_grasp_rate": float(np.mean([r["grasped"] for r in rows])),
            "random_peak_hand_speed_m_s": float(np.median(peaks))}


# ------------------------------------------------------------------------------------- checks
@dataclass(frozen=True)
class Check:
    name: str
    passed: bool
    detail: str


def verdicts(r: dict) -> list[Check]:
    """The pass/fail verdict of every check on the figures of ``run`` (the network checks only
    where ``run`` ran them)."""
    scene_checks = [
        Check("ball in view at every start", r["in_view_fraction"] == 1.0,
              f"{r['in_view_fraction']:.0%} of {r['positions']} grid positions"),
        Check("ball within the distance sensor's range", r["eye_distance_max_m"] < 0.5,
              f"{r['eye_distance_min_m'] * 100:.0f}-{r['eye_distance_max_m'] * 100:.0f} cm "
              "from the eyes (Eq. 3: up to 50 cm)"),
        Check("no part of the robot touches the ball at the start", r["clearance_min_m"] > 0,
              f"closest body {r['clearance_min_m'] * 100:.1f} cm from its surface"),
        Check("palm at least 10 cm from the ball at the start", r["palm_gap_min_m"] >= 0.10,
              f"{r['palm_gap_min_m'] * 100:.1f} cm"),
        Check("every start within reach", r["reach_error_max_m"] < 0.01,
              f"palm-on-ball posture error at most {r['reach_error_max_m'] * 1000:.2f} mm"),
        Check("scripted reach-and-grasp grasps at all 45 points",
              r["scripted_grasps"] == r["scripted_points"],
              f"{r['scripted_grasps']}/{r['scripted_points']}"),
    ]
    if "reflex_grasp_rate_touched" not in r:
        return scene_checks
    return scene_checks + [
        Check("grasp reflex: a palm touch closes the hand (majority)",
              r["reflex_grasp_rate_touched"] >= 0.7
              and r["reflex_grasp_rate_untouched"] <= 0.2,
              f"{r['reflex_grasp_rate_touched']:.0%} touched, "
              f"{r['reflex_grasp_rate_untouched']:.0%} untouched"),
        Check("no grasp reflex without reflexes (pre*)",
              abs(r["noreflex_grasp_rate_touched"] - r["noreflex_grasp_rate_untouched"]) < 0.2,
              f"{r['noreflex_grasp_rate_touched']:.0%} touched, "
              f"{r['noreflex_grasp_rate_untouched']:.0%} untouched"),
        Check("orienting reflex: the head turns toward the ball (majority)",
              r["reflex_head_turn_rate"] > 0.5,
              f"{r['reflex_head_turn_rate']:.0%} (image closer to the centre, trunk "
              f"included: {r['reflex_image_closer_rate']:.0%})"),
        Check("no orienting without reflexes (pre*)", r["noreflex_head_turn_rate"] < 0.5,
              f"{r['noreflex_head_turn_rate']:.0%} (image closer: "
              f"{r['noreflex_image_closer_rate']:.0%})"),
        Check("random networks reach in far fewer than half the trials",
              r["random_reach_rate"] < 0.25 and r["random_reach_rate_high"] < 0.5,
              f"reach {r['random_reach_rate']:.0%} (95 % interval over "
              f"{r['random_networks']} networks {r['random_reach_rate_low']:.0%}-"
              f"{r['random_reach_rate_high']:.0%}), grasp {r['random_grasp_rate']:.0%}, "
              f"fitness {r['random_fitness']:.4f}"),
    ]


def run(world: World | None = None, grid: int = 7, networks: int = REFLEX_NETWORKS,
        chance_networks: int = CHANCE_NETWORKS, seed: int = 0, scene_only: bool = False,
        reflex_inputs: ReflexInputs = ReflexInputs.HAND_SET) -> dict:
    """Every check on the shipped world (or ``world``): the figures and ``checks``, a list of
    ``{name, passed, detail}``; ``passed`` is True when every check passed. ``scene_only``:
    the scene's checks and the scripted grasps only (no networks). ``reflex_inputs``: the
    reflex checks under that lever (``levers.ReflexInputs``)."""
    world = world or World()
    t0 = time.perf_counter()
    r = {"reflex_inputs": ReflexInputs(reflex_inputs).value,
         "physics_dt": world.config.physics_dt, "max_joint_speed": world.config.max_joint_speed,
         "sectors": world.config.sectors.__dict__}
    r.update(scene_geometry(world, grid))
    r.update(scene(world, grid))
    r.update(scripted_grasps(world))
    if not scene_only:
        for tag, on in (("reflex", True), ("noreflex", False)):
            r.update({f"{tag}_{k}": v
                      for k, v in reflex_rates(world, on, networks, seed,
                                               reflex_inputs).items()})
        r.update(chance(world, chance_networks, seed + 1))
    r["checks"] = [c.__dict__ for c in verdicts(r)]
    r["passed"] = all(c["passed"] for c in r["checks"])
    r["seconds"] = time.perf_counter() - t0
    return r


def format_report(r: dict) -> str:
    lines = [f"{'PASS' if c['passed'] else 'FAIL'}  {c['name']}: {c['detail']}"
             for c in r["checks"]]
    lines.append(f"ball centre {r['arm_fraction_min']:.2f}-{r['arm_fraction_max']:.2f} arm "
                 f"lengths from the shoulder ({r['arm_length_m']:.3f} m), "
                 f"{r['elevation_min_deg']:+.0f} to {r['elevation_max_deg']:+.0f} deg from "
                 f"shoulder height, {r['lateral_min_m'] * 100:.0f}-{r['lateral_max_m'] * 100:.0f}"
                 f" cm right of the midline (sphere radius {r['sectors']['radius']} m)")
    random = (f", random networks {r['random_peak_hand_speed_m_s']:.2f} m/s"
              if "random_peak_hand_speed_m_s" in r else "")
    lines.append(f"scripted reach peak hand speed {r['scripted_peak_hand_speed_m_s']:.2f} m/s"
                 f"{random} (medians); physics step {r['physics_dt']} s, joint speed bound "
                 f"{r['max_joint_speed']} rad/s; {r['seconds']:.0f} s")
    return "\n".join(lines)
