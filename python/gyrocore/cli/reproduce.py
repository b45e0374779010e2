"""``gyrocore reproduce``: the papers' experiments on simulated data, paper values beside ours."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import paper
from .._checks import require_choice
from ._common import add_command, add_overwrite_option, named_path, refuse_existing


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(
        sub,
        "reproduce",
        "rerun the papers' experiments on simulated data (seed 0): print paper beside ours, write the figures",
        "gyrocore reproduce hong-table-1 hong-table-1-sensitivity --out figures",
        run,
    )
    p.add_argument("names", nargs="*", metavar="NAME",
                   help=f"experiments (default: all, about 15 s; docs/simulation.md gives each one's time): "
                        f"{', '.join(paper.REPRODUCTIONS)}")
    p.add_argument("-o", "--out", type=named_path, default=Path("."),
                   help="folder for the figures (PNG; created if missing; default: the current folder)")
    p.add_argument("--no-figures", action="store_true", help="print the tables only")
    add_overwrite_option(p)


def run(args: argparse.Namespace) -> int:
    names = list(dict.fromkeys(args.names)) or list(paper.REPRODUCTIONS)  # a name given twice runs once
    for name in names:  # before anything runs, so a typo costs no time
        require_choice("experiment", name, paper.REPRODUCTIONS)
    if not args.no_figures:
        refuse_existing([args.out / paper.REPRODUCTIONS[name][1] for name in names], args.overwrite,
                        folders_exist=False)  # the figures' folder is made
    for i, name in enumerate(names):
        if i:
            print()
        paper.reproduce(name, out_dir=None if args.no_figures else args.out, overwrite=args.overwrite)
    return 0
