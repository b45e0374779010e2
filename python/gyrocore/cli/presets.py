"""``gyrocore presets``: the presets and their parameters."""

from __future__ import annotations

import argparse
import json

from ..pipeline import preset_names, preset_params, recommended_preset
from ._common import add_command


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(sub, "presets", "list the presets and their parameters", "gyrocore presets --json", run)
    p.add_argument("--json", action="store_true", help="print JSON")


def run(args: argparse.Namespace) -> int:
    params = {name: preset_params(name) for name in preset_names()}
    if args.json:
        print(json.dumps({"recommended": recommended_preset(), "presets": params}, indent=2))
    else:
        for name, p in params.items():
            mark = " (recommended)" if name == recommended_preset() else ""
            print(f"{name}{mark}: " + ", ".join(f"{k}={v}" for k, v in p.items()))
    return 0
