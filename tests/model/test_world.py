"""The DART world against the official iCub model and the paper's set-up (sections III, III-A),
stepped by the living model's servo (``servo.Servo``)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from dart_reach.model import icub
from dart_reach.model.scripted import grasp_posture
from dart_reach.model.servo import Servo
from dart_reach.model.world import (N_SECTORS, SYSTEMATIC_FRACTIONS, SkeletonError, World,
                              WorldConfig, sector_angles)


@pytest.fixture(scope="module")
def world():
    return World()


@pytest.fixture(scope="module")
def servo(world):
    return Servo(world)


# ------------------------------------------------------------- kinematics vs the official model
def test_forward_kinematics_matches_official_icub_model(world):
    """r_hand and head frames within 1 mm (and 1e-6 in rotation) of the official iCubGazeboV2_5
    URDF, loaded independently by pinocchio, over 150 random configurations within limits."""
    pin = pytest.importorskip("pinocchio")
    icub_models = pytest.importorskip("icub_models")
    model = pin.buildModelFromUrdf(icub_models.get_model_file("iCubGazeboV2_5"))
    data = model.createData()
    robot = world.robot
    saved = robot.getPositions()
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(150):
        q = rng.uniform(world.lower, world.upper)
        robot.setPositions(q)
        q_ref = pin.neutral(model)
        for name in icub.ARM_HEAD_TORSO_JOINTS:
            q_ref[model.idx_qs[model.getJointId(name)]] = q[
                robot.getJoint(name).getIndexInSkeleton(0)]
        pin.framesForwardKinematics(model, data, q_ref)
        for frame in ("r_hand", "head"):
            ref = data.oMf[model.getFrameId(frame)]
            ours = robot.getBodyNode(frame).getWorldTransform()
            worst = max(worst, np.linalg.norm(ours.translation() - ref.translation))
            assert np.allclose(ours.rotation(), ref.rotation, atol=1e-6), frame
    robot.setPositions(saved)
    assert worst < 1e-3, f"largest position error {worst * 1000:.3f} mm"


def test_skeleton_has_the_papers_degrees_of_freedom(world):
    robot = world.robot
    for name in icub.ARM_HEAD_TORSO_JOINTS + icub.FINGER_JOINTS:
        assert robot.getJoint(name) is not None, name
    assert robot.getNumDofs() == 13 + 15
    assert robot.getRootJoint().getType() == "WeldJoint"  # the pelvis on its stick
    # Total mass: the official upper body (~18.4 kg with the lumped finger bases).
    assert 17.0 < robot.getMass() < 20.0


# ------------------------------------------------------------------ sectors
def test_sectors_lie_on_the_sphere_in_front_and_to_the_right(world):
    points = world.systematic_points()
    assert points.shape == (45, 3)
    assert len({tuple(np.round(p, 9)) for p in points}) == 45
    r = np.linalg.norm(points - world.neck_centre, axis=1)
    assert np.allclose(r, world.config.sectors.radius)
    rel = points - world.neck_centre
    assert (rel[:, 0] < 0).all(), "in front of the robot (-x)"
    assert (rel[:, 1] >= -1e-12).all(), "to the right of the neck (+y)"
    rng = np.random.default_rng(0)
    for k in range(N_SECTORS):
        az0, el0 = sector_angles(world.config.sectors, k, 0, 0)
        az1, el1 = sector_angles(world.config.sectors, k, 1, 1)
        for _ in range(20):
            rel = world.random_sector_point(k, rng) - world.neck_centre
            az = np.degrees(np.arctan2(rel[1], -rel[0]))
            el = np.degrees(np.arcsin(rel[2] / np.linalg.norm(rel)))
            assert az0 - 1e-9 <= az <= az1 + 1e-9 and el0 - 1e-9 <= el <= el1 + 1e-9
    assert SYSTEMATIC_FRACTIONS[0] == (0.5, 0.5)


@pytest.mark.parametrize("sector", range(N_SECTORS))
def test_every_sector_is_reachable(world, sector):
    """Some posture within the joint limits puts the palm within 2 cm of the ball, at the
    corners, the centre and random points of every sector."""
    rng = np.random.default_rng(sector)
    fractions = [(0, 0), (1, 0), (0, 1), (1, 1), (0.5, 0.5)] + [tuple(rng.random(2))
                                                                 for _ in range(3)]
    for u, v in fractions:
        solution = grasp_posture(world, world.sector_point(sector, u, v))
        assert np.all(solution.q >= world.lower - 1e-12) and np.all(solution.q <= world.upper)
        assert solution.palm_error < 0.02, (sector, u, v, solution.palm_error)


# ------------------------------------------------------------------ control
TRACKING_BOUND = 0.01  # rad: every joint within this of its target after 2 s of hold


def test_joints_track_targets_within_bound_after_two_seconds(world, servo):
    rng = np.random.default_rng(3)
    far = world.sector_point(6, 0.0, 0.0) + [0.0, -0.5, 0.0]  # ball out of the arm's way
    worst = 0.0
    for _ in range(6):
        servo.reset(far)
        targets = rng.uniform(-0.9, 0.9, 14)
        for _ in range(20):
            servo.step(targets)
        q_des = world.motor_lower + (targets + 1) / 2 * (world.motor_upper - world.motor_lower)
        error = np.abs(world.motor_positions() - q_des)
        worst = max(worst, error.max())
        # every finger joint follows the one hand motor
        fingers = world.joint_positions()[world.layout.finger_dofs]
        assert np.abs(fingers - q_des[13]).max() < TRACKING_BOUND
    assert worst < TRACKING_BOUND, f"worst tracking error {worst:.4f} rad"


def test_joint_speed_is_bounded(world, servo):
    """From one end of the range to the other, no joint moves faster than the speed bound
    (30% for the springs' transient: the commanded position moves in steps of 0.1 s), and the
    move takes the time the bound says."""
    servo.reset(world.sector_point(6, 0, 0) + [0.0, -0.5, 0.0])
    v_max = world.config.max_joint_speed
    t = np.full(14, -1.0)
    for _ in range(30):
        servo.step(t)
    t[:] = 1.0
    start = world.motor_positions()
    peak = 0.0
    for _ in range(5):
        servo.step(t)
        peak = max(peak, np.abs(world.robot.getVelocities()).max())
    moved = np.abs(world.motor_positions() - start)
    assert peak < 1.3 * v_max
    assert moved.max() < v_max * 0.5 + 0.01  # 0.5 s: not yet across the widest ranges
    assert peak > 0.8 * v_max


def test_fingers_all_follow_the_hand_motor(world, servo):
    servo.reset(world.sector_point(6, 0, 0) + [0, -0.5, 0])
    for target, expected in ((1.0, np.pi / 2), (-1.0, 0.0), (0.0, np.pi / 4)):
        t = world.home_targets.copy()
        t[13] = target
        for _ in range(10):
            servo.step(t)
        fingers = world.joint_positions()[world.layout.finger_dofs]
        assert fingers.shape == (15,)
        assert np.allclose(fingers, expected, atol=0.02), (target, fingers)
        assert world.motor_positions()[13] == pytest.approx(fingers.mean())


def test_joint_never_stays_stuck_at_a_limit(world, servo):
    """Drive the shoulder and elbow to their limits (gravity pulling), then away: they leave."""
    servo.reset(world.sector_point(6, 0, 0) + [0, -0.5, 0])
    t = world.home_targets.copy()
    t[[6, 9]] = (-1.0, 1.0)
    for _ in range(20):
        servo.step(t)
    q = world.motor_positions()
    assert q[6] == pytest.approx(world.motor_lower[6], abs=0.02)
    assert q[9] == pytest.approx(world.motor_upper[9], abs=0.02)
    t[[6, 9]] = 0.0
    for _ in range(10):
        servo.step(t)
    q = world.motor_positions()
    mid = (world.motor_lower + world.motor_upper) / 2
    assert abs(q[6] - mid[6]) < TRACKING_BOUND and abs(q[9] - mid[9]) < TRACKING_BOUND


# ------------------------------------------------------------------ ball
def test_ball_swings_after_a_push_and_returns_to_rest(world, servo):
    rest = world.sector_point(0, 0.5, 0.5)
    servo.reset(rest)
    assert np.allclose(world.ball_position(), rest)
    for _ in range(10):  # untouched, it hangs still
        servo.step(world.home_targets)
    assert np.linalg.norm(world.ball_position() - rest) < 1e-6
    world.ball_skeleton.setVelocities([1.0, 0.0])  # rad/s about the pivot: ~8 cm swing
    excursion = 0.0
    for _ in range(30):
        servo.step(world.home_targets)
        excursion = max(excursion, np.linalg.norm(world.ball_position() - rest))
    assert excursion > 0.05, "the push makes it swing"
    for _ in range(250):
        servo.step(world.home_targets)
    assert np.linalg.norm(world.ball_position() - rest) < 0.003, "back to rest"
    assert np.abs(world.ball_skeleton.getVelocities()).max() < 0.02


def test_ball_never_rises_to_its_pivot(world, servo):
    """Hit as hard as the arm could ever hit it (10 m/s), the ball stays below its pivot."""
    rest = world.sector_point(4, 0.5, 0.5)
    length = world.config.ball.string_length
    for velocity in ([30.0, 0.0], [0.0, -30.0], [21.0, 21.0]):  # rad/s: 12 m/s at the ball
        servo.reset(rest)
        world.ball_skeleton.setVelocities(velocity)
        highest = -np.inf
        for _ in range(20):
            servo.step(world.home_targets)
            highest = max(highest, world.ball_position()[2])
        assert highest < rest[2] + length - 0.01, velocity
        assert world.is_finite()


# ------------------------------------------------------------------ determinism and reset
def _trajectory(servo: Servo, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    world = servo.world
    servo.reset(world.sector_point(4, 0.5, 0.5))
    out = []
    for _ in range(30):
        servo.step(rng.uniform(-1, 1, 14))
        out.append(np.concatenate([world.joint_positions(), world.ball_position()]))
    return np.array(out)


def test_same_seed_same_trajectory_and_reset_is_complete(world, servo):
    a = _trajectory(servo, 11)
    b = _trajectory(servo, 11)  # the same world after reset
    c = _trajectory(Servo(World()), 11)  # a fresh world
    assert np.array_equal(a, b) and np.array_equal(a, c)
    d = _trajectory(servo, 12)
    assert not np.array_equal(a, d)


def test_a_study_runs_the_substeps_by_its_own_loop_and_gives_them_back(world):
    """``Servo.use_substeps``: ``advance`` runs the loop given (here the model's own, counted),
    the trajectory unchanged; ``None`` gives the model's loop back; a loop must be callable."""
    servo = Servo(world)
    model, calls = servo.substeps, []

    def counted():
        calls.append(1)
        model()
    servo.use_substeps(counted)
    a = _trajectory(servo, 11)
    assert len(calls) == 30 and np.array_equal(a, _trajectory(Servo(world), 11))
    servo.use_substeps()
    assert servo.substeps is model
    _trajectory(servo, 11)
    assert len(calls) == 30
    with pytest.raises(TypeError, match="callable"):
        servo.use_substeps(3)


# ------------------------------------------------------------------ bad input
def test_bad_inputs_raise_clear_errors(world, servo, tmp_path):
    with pytest.raises(SkeletonError, match="not found"):
        World(WorldConfig(skeleton=tmp_path / "missing.urdf"))
    garbage = tmp_path / "garbage.urdf"
    garbage.write_text("this is not xml")
    with pytest.raises(SkeletonError, match="not a URDF"):
        World(WorldConfig(skeleton=garbage))
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'>")
    with pytest.raises(SkeletonError, match="could not be parsed"):
        World(WorldConfig(skeleton=broken))
    armless = tmp_path / "armless.urdf"
    armless.write_text(
        "<robot name='x'><link name='a'/><link name='b'/><joint name='j' type='revolute'>"
        "<parent link='a'/><child link='b'/><limit lower='-1' upper='1' effort='1' "
        "velocity='1'/></joint></robot>")
    with pytest.raises(SkeletonError, match="lacks"):
        World(WorldConfig(skeleton=armless))
    for sector in (9, -1, 1.5, "3"):
        with pytest.raises(ValueError, match="sector"):
            world.sector_point(sector, 0.5, 0.5)
    with pytest.raises(ValueError, match="14 motor targets"):
        servo.step(np.zeros(13))
    commanded = servo.q_cmd.copy()
    with pytest.raises(ValueError, match="finite"):
        servo.step(np.r_[np.zeros(13), np.nan])
    assert np.array_equal(servo.q_cmd, commanded)  # a refused command moves no motor
    with pytest.raises(ValueError, match="ball position"):
        world.reset([0.0, np.inf, 0.0])
    with pytest.raises(ValueError, match="multiple"):
        WorldConfig(physics_dt=0.03)
    for bad in (0.0, -0.01, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="physics_dt must be a positive number"):
            WorldConfig(physics_dt=bad)


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=300)


def test_cli_bad_input_is_one_line_and_exit_code_2(tmp_path):
    for args, needle in ((["reach", "--sector", "9"], "sector"),
                         (["reach", "--skeleton", str(tmp_path / "nope.urdf")], "not found")):
        result = _cli(*args)
        assert result.returncode == 2, result.stderr
        lines = [l for l in result.stderr.splitlines() if l.startswith("dart-reach")]
        assert len(lines) == 1 and needle in lines[0]
        assert "Traceback" not in result.stderr


def test_cli_scripted_reach_touches_the_ball():
    result = _cli("reach", "--seconds", "3")
    assert result.returncode == 0, result.stderr
    assert "segments that touched the ball: r_hand" in result.stdout
