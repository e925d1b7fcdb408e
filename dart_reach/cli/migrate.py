"""``migrate``: give a run written before the ledger (``ledger.json``, the SHA-256 of every
file of a run) its ledger, once its files are checked (``integrity.migrate``)."""

from __future__ import annotations

from .arguments import command, path_arg


def register_migrate(subparsers) -> None:
    p = command(subparsers, "migrate", "record the files of a run written before its ledger "
                                       "(ledger.json) once they are checked, and say how each "
                                       "was checked; every command refuses such a run until "
                                       "then")
    p.epilog = ("Each file is checked as far as it can be: against the digests an older "
                "ledger in manifest.json recorded, else (in a git work tree) against the "
                "content committed at HEAD, else read whole (every zip entry's CRC of an "
                ".npz, every page of a parquet table, the manifest's JSON, a recording's "
                "chunks). A file that fails is named and nothing is written. Nothing but "
                "ledger.json is written; a run that has one is checked against it and left "
                "as it is.")
    p.add_argument("run_dir", type=path_arg, metavar="RUN_DIR", help="a run directory of 'train'")
    p.set_defaults(func=cmd_migrate)


def cmd_migrate(args) -> int:
    from .. import integrity
    from ..evolution.rundir import RunError
    from ..files import DirectoryLock

    out = args.run_dir
    if not out.is_dir():
        raise RunError(f"{out}: no such run directory" if not out.exists()
                       else f"{out}: not a directory")
    if not (out / integrity.MANIFEST).is_file():
        raise RunError(f"{out}: not a run directory (no {integrity.MANIFEST})")
    if integrity.has_ledger(out):  # read only: no lock taken
        found = integrity.migrate(out)
    else:
        with DirectoryLock(out):
            found = integrity.migrate(out)
    print("\n".join(found.lines()))
    return 0
