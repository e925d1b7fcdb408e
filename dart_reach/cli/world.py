"""The simulated world without evolution: ``reach`` (a scripted reach-and-grasp), ``scenes``
(where the shipped scenes hang the ball, relative to the arm) and ``versions`` (the model's
registered versions)."""

from __future__ import annotations

from .arguments import add_scene, command, path_arg, world_config


def register_reach(subparsers) -> None:
    p = command(subparsers, "reach", "run a scripted reach-and-grasp and print what happened")
    p.add_argument("--sector", type=int, default=4, help="ball sector 0..8 (default 4)")
    p.add_argument("--seconds", type=float, default=5.0, help="simulated seconds (default 5)")
    p.add_argument("--skeleton", type=path_arg, default=None,
                   help="robot model (URDF; default: the shipped skeleton)")
    add_scene(p)
    p.set_defaults(func=cmd_reach)


def cmd_reach(args) -> int:
    """Build the world, run a short scripted reach-and-grasp and say what happened."""
    import numpy as np

    from ..model.icub import HAND_SEGMENTS
    from ..model.scripted import ScriptedReach
    from ..model.servo import Servo
    from ..model.versions import CURRENT_MODEL_VERSION, model_version
    from ..model.world import World, WorldConfig

    if not (np.isfinite(args.seconds) and 0 < args.seconds <= 3600):
        raise ValueError(f"--seconds must be a number of simulated seconds in (0, 3600], got "
                         f"{args.seconds:g}")
    world = World(world_config(args, model_version(CURRENT_MODEL_VERSION).world(
        WorldConfig(skeleton=args.skeleton))))
    servo = Servo(world)  # the living model's motors and touch
    ball = world.sector_point(args.sector, 0.5, 0.5)
    servo.reset(ball)
    reach = ScriptedReach(world, ball)
    print(f"world: {world.robot.getNumBodyNodes()} robot bodies, {world.robot.getNumDofs()} "
          f"joints, ball r={world.config.ball.radius} m in sector {args.sector} at "
          f"{np.round(ball, 3).tolist()} m")
    print(f"scripted grasp posture found (palm error {reach.solution.palm_error * 1000:.1f} mm)")
    print(f"{'t [s]':>6} {'hand-ball [m]':>14}  contacts")
    touched = set()
    for k in range(int(round(args.seconds / world.config.control_dt))):
        contacts = world.hand_contacts()
        touched.update(np.array(HAND_SEGMENTS)[contacts])
        servo.step(reach.targets(contacts))
        if k % 5 == 4:
            names = [n.removeprefix("r_hand_") for n in np.array(HAND_SEGMENTS)[contacts]]
            d = np.linalg.norm(world.hand_position() - world.ball_position())
            print(f"{world.time:6.1f} {d:14.3f}  {', '.join(names) or '-'}")
    print(f"segments that touched the ball: {', '.join(sorted(touched)) or 'none'}")
    return 0


def register_scenes(subparsers) -> None:
    p = command(subparsers, "scenes", "list the shipped scenes (where the ball hangs) and their "
                                      "geometry relative to the arm")
    p.set_defaults(func=cmd_scenes)


def register_versions(subparsers) -> None:
    p = command(subparsers, "versions", "list the model versions (each a whole model: "
                                        "numerics, scene, self-collision, levers) and the one "
                                        "new runs use")
    p.set_defaults(func=cmd_versions)


def cmd_versions(args) -> int:
    """The table of model versions (``model.versions.versions_table``)."""
    from ..model.versions import versions_table

    print(versions_table(), end="")
    return 0


def cmd_scenes(args) -> int:
    """The shipped scenes and where their ball positions lie relative to the right arm."""
    from ..model.scenes import load_scene, scene_names
    from ..model.versions import CURRENT_MODEL_VERSION, model_version
    from ..studies.validate import scene_geometry
    from ..model.world import World

    print(f"{'scene':<22}{'radius':>7}  {'ball centre / arm length':<26}"
          f"{'elevation from shoulder':<25}{'lateral from midline':<22}description")
    for name in scene_names():
        scene = load_scene(name)
        g = scene_geometry(World(scene.world()))
        mark = " *" if name == model_version(CURRENT_MODEL_VERSION).scene else ""
        print(f"{name + mark:<22}{scene.sectors.radius:>6.3f}m  "
              f"{g['arm_fraction_min']:.2f} / {g['arm_fraction_median']:.2f} / "
              f"{g['arm_fraction_max']:.2f}{'':<8}"
              f"{g['elevation_min_deg']:+.0f} / {g['elevation_median_deg']:+.0f} / "
              f"{g['elevation_max_deg']:+.0f} deg{'':<7}"
              f"{g['lateral_min_m'] * 100:.0f} to {g['lateral_max_m'] * 100:.0f} cm{'':<10}"
              f"{scene.description}")
    print(f"(min / median / max over a 7 x 7 grid of every sector; arm length "
          f"{g['arm_length_m']:.3f} m, shoulder to palm centre, elbow straight; * the scene "
          f"of model version {CURRENT_MODEL_VERSION}, the one new runs use)")
    return 0
