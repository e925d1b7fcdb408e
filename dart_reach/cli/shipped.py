"""What the package ships besides the model: ``robots`` (the evolved robots files) and
``conditions`` (the training conditions)."""

from __future__ import annotations

from .arguments import command


def register_robots(subparsers) -> None:
    p = command(subparsers, "robots", "list the shipped evolved robots (their run, phase and "
                                      "budget; 'watch --shipped RUN' shows one)")
    p.set_defaults(func=cmd_robots)


def cmd_robots(args) -> int:
    """The shipped robots files (``robots.index()``)."""
    from ..robots import index

    rows = [("run", "condition/phase", "robots", "generations", "replications", "scene", "file")]
    for r in index():
        b = r["budget"] or {}
        rows.append((str(r["run"] or "?"), f"{r['condition']}/{r['phase']}", str(r["robots"]),
                     *(str(b.get(k) or "?") for k in ("generations", "replications", "scene")),
                     r["file"]))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    for row in rows:
        print("  ".join(x.ljust(w) for x, w in zip(row, widths)) + "  " + row[-1])
    return 0


def register_conditions(subparsers) -> None:
    p = command(subparsers, "conditions", "list the shipped conditions")
    p.set_defaults(func=cmd_conditions)


def cmd_conditions(args) -> int:
    from ..evolution.conditions import list_conditions

    print(f"{'name':<16}{'paper':<22}{'phases':<26}{'generations':<17}description")
    for c in list_conditions():
        phases = " -> ".join(p.name for p in c.phases)
        budgets = " + ".join(str(p.generations) for p in c.phases)
        print(f"{c.name:<16}{c.notation:<22}{phases:<26}{budgets:<17}{c.description}")
    return 0
