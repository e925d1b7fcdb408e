"""``watch`` (one trial of an evolved robot in the Rerun viewer, or drawn by the numpy camera
where none opens) and ``video`` (a trial recording rendered into an MP4 by the headless viewer,
or by the numpy camera where the viewer cannot render)."""

from __future__ import annotations

import shlex

from .arguments import command, non_negative, path_arg, positive


def register_watch(subparsers) -> None:
    p = command(subparsers, "watch", "run one trial of an evolved robot (a shipped one, or a "
                                     "trained run's best with --run) and show it in the Rerun "
                                     "viewer (without one: pictures of it beside the "
                                     "recording)")
    p.add_argument("phase", nargs="?", default=None, metavar="PHASE",
                   help="pre, gross or fine (default: the most developed phase available)")
    p.add_argument("--condition", default="standard",
                   help="the condition the robot was trained in")
    p.add_argument("--run", type=path_arg, default=None, metavar="RUN_DIR",
                   help="watch this trained run's robot (default: a shipped robot)")
    p.add_argument("--shipped", default=None, metavar="NAME",
                   help="a shipped robot of the shipped run NAME (see 'robots'; default: "
                        "the run that trained the phase longest)")
    p.add_argument("--replication", type=non_negative, default=None, metavar="R",
                   help="the robot's replication (default: the best replication)")
    p.add_argument("--rank", type=non_negative, default=0,
                   help="the robot's rank in its replication's final population (0 = best)")
    p.add_argument("--sector", type=int, default=4, choices=range(9), metavar="K",
                   help="the ball at the centre of sector K, 0..8")
    p.add_argument("--senses", default="normal",
                   choices=("normal", "no-touch", "no-sight", "nothing"),
                   help="sensory condition (Fig. 9)")
    p.add_argument("--out", type=path_arg, default=None, metavar="FILE.rrd",
                   help="the recording, a new file (default: recordings/watch/<condition>-"
                        "<phase>-sector<K>.rrd, or -2.rrd, ... where taken); its layout is "
                        "written beside it (.rbl), and where no viewer opens the numpy "
                        "camera's pictures (.png strip, .gif)")
    p.add_argument("--no-viewer", action="store_true",
                   help="only write the files and pictures, even where there is a display")
    p.set_defaults(func=cmd_watch)


def cmd_watch(args) -> int:
    """One trial of an evolved robot in the Rerun viewer (or saved for it)."""
    from ..viewing.watch import watch

    watched = watch(args.phase, args.condition, args.replication, args.rank, args.sector,
                    args.senses, args.run, args.out, viewer=False if args.no_viewer else None,
                    shipped=args.shipped)
    m = watched.measures
    print(f"{watched.robot}\nsector {args.sector}, {args.senses} senses: "
          f"{'reached' if m['reached'] else 'no reach'}, "
          f"{'grasped' if m['grasped'] else 'no grasp'}, fitness {m['fitness']:.4f}")
    if watched.viewer_pid is not None:
        print(f"the Rerun viewer is opening {watched.recording} (PID {watched.viewer_pid})")
    else:
        strip, animation = watched.pictures
        print(f"drew the trial with the numpy camera: {strip} (a few instants side by side) "
              f"and {animation} (the whole trial, real time; opens in a browser)")
        print(f"wrote {watched.recording} and its layout {watched.layout}; open them where "
              f"there is a display with:\n  {shlex.join(watched.open_command)}")
    return 0


def register_video(subparsers) -> None:
    p = command(subparsers, "video", "render a trial recording frame by frame into a video "
                                     "(MP4): the Rerun viewer, headless, or where it cannot "
                                     "render the numpy camera")
    p.add_argument("rrd", type=path_arg, metavar="TRIAL.rrd",
                   help="a trial recording (watch, evaluate or train --record-every)")
    p.add_argument("out", type=path_arg, metavar="OUT.mp4", help="the video, a new file")
    p.add_argument("--layout", type=path_arg, default=None, metavar="FILE.rbl",
                   help="the viewer's layout (default: the trial layout of 'dart-reach "
                        "watch' and the post-evaluation; the camera draws the 3D scene alone)")
    p.add_argument("--fps", type=positive, default=10,
                   help="frames per simulated second (10 = one per control step, real time)")
    p.add_argument("--size", default="1280x720", metavar="WxH", help="frame size in pixels")
    p.add_argument("--renderer", default=None, metavar="{viewer,camera}",
                   help="viewer: the Rerun viewer with the layout (needs a Vulkan driver); "
                        "camera: the numpy camera, the 3D scene alone, on any machine "
                        "(default: the viewer where it can render, else the camera)")
    p.set_defaults(func=cmd_video)


def cmd_video(args) -> int:
    """A trial recording rendered frame by frame by the headless viewer into a video."""
    from ..viewing.headless import renderer_missing
    from ..viewing.video import CannotRender, render_video

    try:
        result = render_video(args.rrd, args.out, layout=args.layout, fps=args.fps,
                              size=args.size, progress=True, renderer=args.renderer)
    except CannotRender as exc:  # this machine, once the input is known to be right: one line
        raise ValueError(f"cannot render a video here: {exc}") from None
    print(f"wrote {result.path}: {result.frames} frames, {result.sim_seconds:g} simulated s, "
          f"rendered in {result.wall_seconds:.0f} s")
    if result.renderer == "camera":
        why = ("" if args.renderer else
               f" (the Rerun viewer cannot render here: {renderer_missing()})")
        print(f"drawn by the numpy camera: the 3D scene alone, no time series"
              f"{'; --layout not used' if args.layout else ''}{why}")
    return 0
