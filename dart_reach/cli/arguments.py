"""What the commands share on their command lines: argparse types that refuse bad values with
one line (integers with a minimum, worker counts, a physics step), the options several commands
take (``--workers``/``--ray``, ``--scene``), the help formatter that shows every default, and
the parser whose usage errors are one line and exit code 2."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path


def int_at_least(minimum: int):
    """An argparse type: an integer >= ``minimum``."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}")
        return value
    return parse


positive, non_negative = int_at_least(1), int_at_least(0)


def path_arg(text: str) -> Path:
    """An argparse type: a path, never empty (``Path("")`` would be the working directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a path, got an empty one")
    return Path(text)


def generations(text: str) -> tuple[int, ...]:
    """An argparse type: generations, comma-separated positive integers ("50,100")."""
    try:
        values = tuple(sorted({positive(g.strip()) for g in text.split(",")}))
    except argparse.ArgumentTypeError:
        values = ()
    if not values:
        raise argparse.ArgumentTypeError(f"expected generations separated by commas (e.g. "
                                         f"50,100), got {text!r}")
    return values


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # macOS, Windows
        return os.cpu_count() or 1


def workers(text: str) -> int:
    """An argparse type: local worker processes, 1 to the machine's cores. More are refused
    rather than capped: the work is CPU-bound, so they would not finish sooner (results are
    identical for any number of workers), and each process holds its own memory (a worker's
    peak: docs/results/benchmarks.md, ``worker_peak_rss_mb``)."""
    n, available = positive(text), cores()
    if n > available:
        raise argparse.ArgumentTypeError(
            f"{n} is more than the {available} cores of this machine: extra processes would not "
            f"finish sooner (the work is CPU-bound) and each takes its own memory; use "
            f"{available} or fewer, or --ray for a cluster")
    return n


def physics_dt(text: str) -> float:
    """An argparse type: a physics step in s, positive, finite, dividing the control step."""
    from ..model.world import WorldConfig

    control = WorldConfig().control_dt
    try:
        dt = float(text)
    except ValueError:
        dt = math.nan
    if not (math.isfinite(dt) and dt > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number of seconds, got {text!r}")
    substeps = control / dt
    if substeps < 1 or abs(substeps - round(substeps)) > 1e-9:
        raise argparse.ArgumentTypeError(
            f"{text} s does not divide the control step ({control:g} s) a whole number of "
            f"times: use {control:g}/n, e.g. 0.02 or 0.01")
    return dt


class Help(argparse.HelpFormatter):
    """Every option's default in its help (unless the help already says it)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if (action.option_strings and action.nargs != 0 and "default" not in text
                and default is not None and default is not argparse.SUPPRESS
                and default != []):
            text += " (default: %(default)s)"
        return text


class Parser(argparse.ArgumentParser):
    """Usage errors as one line and exit code 2, like every other bad input."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def command(subparsers, name: str, text: str) -> argparse.ArgumentParser:
    """A command's parser: ``text`` is both its line in ``dart-reach --help`` and its
    description."""
    return subparsers.add_parser(name, help=text, description=text, formatter_class=Help)


def add_workers(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=workers, default=None,
                   help="local processes, at most the machine's cores (default: every core; "
                        "1 = serial)")
    p.add_argument("--ray", default=None, metavar="ADDRESS",
                   help="evaluate on a Ray cluster ('auto', 'local' or an address; default: "
                        "none, local processes)")


def add_scene(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scene", default=None, metavar="SCENE",
                   help="where the ball hangs: a shipped scene (see 'scenes') or a scene file "
                        "(default: the scene of the model version new runs use, 'dart-reach "
                        "versions')")


def world_config(args, base=None):
    """``base`` (default: the world of the model version new runs use) with the sectors of
    ``--scene`` if given (and ``--self-collision`` where the command has it)."""
    from dataclasses import replace

    from ..model.scenes import load_scene
    from ..model.versions import CURRENT_MODEL_VERSION, model_version

    base = base or model_version(CURRENT_MODEL_VERSION).world()
    if getattr(args, "self_collision", None) is not None:
        base = replace(base, self_collision=args.self_collision == "on")
    return base if args.scene is None else load_scene(args.scene).world(base)


def add_levers(p: argparse.ArgumentParser) -> None:
    """The model's levers (docs/model/levers.md) and its version, for a new run: a lever given
    beside a version makes the run a named variant of it (``model.versions``)."""
    from ..model.levers import NetworkStart, ReflexInputs, TouchPay
    from ..model.versions import CURRENT_MODEL_VERSION, MODEL_VERSIONS

    def choices(kind):
        return [k.value for k in kind]

    p.add_argument("--reflex-inputs", choices=choices(ReflexInputs), default=None,
                   help="what drives the reflex motors besides the reflex arcs: 'hand-set' "
                        "(only the reflex weights) or 'evolved' (every sensor, evolved weights "
                        "x 0.1, as Fig. 3's caption reads) (default: the model version's)")
    p.add_argument("--touch-pay", choices=choices(TouchPay), default=None,
                   help="p_touch of Eq. 5: 'faces' (touching inner faces / 16), 'binary' (any "
                        "touch = 1) or 'capped' (min(n, 4) / 4) (default: the model version's)")
    p.add_argument("--network-start", choices=choices(NetworkStart), default=None,
                   help="the network's state at a trial's start: 'hold-home' (motor states "
                        "holding the home posture) or 'zero' (every state 0) "
                        "(default: the model version's)")
    p.add_argument("--self-collision", choices=["on", "off"], default=None,
                   help="the arm collides with the body (default: the model version's)")
    p.add_argument("--model-version", type=int, choices=sorted(MODEL_VERSIONS), default=None,
                   help=f"the model version of a new run, a whole model: numerics, scene, "
                        f"self-collision and levers (default: {CURRENT_MODEL_VERSION}, the "
                        f"version new runs use; 'dart-reach versions' lists them; a resumed "
                        f"run keeps its own)")


def levers(args, base=None):
    """``base`` (default ``Levers()``) with the levers ``add_levers``'s options give."""
    from dataclasses import replace

    from ..model.levers import TRIAL_LEVERS, Levers

    return replace(base or Levers(),
                   **{k: getattr(args, k) for k in TRIAL_LEVERS if getattr(args, k) is not None})
