"""``dart-reach``: the command line, a thin layer over the library.

Any error in the user's input (a ValueError or a missing file) becomes one line on stderr and
exit code 2, without a traceback.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np


def cmd_reach(args) -> int:
    """Build the world, run a short scripted reach-and-grasp and say what happened."""
    from .icub import HAND_SEGMENTS
    from .scripted import ScriptedReach
    from .world import World, WorldConfig

    world = World(WorldConfig(skeleton=args.skeleton))
    ball = world.sector_point(args.sector, 0.5, 0.5)
    world.reset(ball)
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
        world.step(reach.targets(contacts))
        if k % 5 == 4:
            names = [n.removeprefix("r_hand_") for n in np.array(HAND_SEGMENTS)[contacts]]
            d = np.linalg.norm(world.hand_position() - world.ball_position())
            print(f"{world.time:6.1f} {d:14.3f}  {', '.join(names) or '-'}")
    print(f"segments that touched the ball: {', '.join(sorted(touched)) or 'none'}")
    return 0


def cmd_bench(args) -> int:
    from . import bench

    results = bench.run(seconds=args.seconds, repeats=args.repeats)
    print(bench.format_table(results))
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2) + "\n")
        print(f"wrote {args.json}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dart-reach",
        description="Reaching and grasping development of a simulated iCub "
                    "(Savastano & Nolfi 2013) on DART.")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("reach", help="run a scripted reach-and-grasp and print what happened")
    p.add_argument("--sector", type=int, default=4, help="ball sector 0..8 (default 4)")
    p.add_argument("--seconds", type=float, default=4.0, help="simulated seconds (default 4)")
    p.add_argument("--skeleton", type=Path, default=None, help="robot model (URDF)")
    p.set_defaults(func=cmd_reach)

    p = sub.add_parser("bench", help="measure simulation speed (see README)")
    p.add_argument("--json", type=Path, default=None, help="also write the figures to FILE")
    p.add_argument("--seconds", type=float, default=20.0, help="simulated s per block")
    p.add_argument("--repeats", type=int, default=5, help="interleaved blocks per figure")
    p.set_defaults(func=cmd_bench)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, FileNotFoundError, NotADirectoryError, PermissionError) as exc:
        print(f"dart-reach: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("dart-reach: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
