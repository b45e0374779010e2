"""``gyrocore presets``: the presets and their parameters."""

from __future__ import annotations

import argparse

from ..pipeline import parameters, preset_names, preset_params, recommended_preset
from ..pipeline_params import _RATE_PARAMETERS
from ._common import add_command, print_json


def register(sub: "argparse._SubParsersAction[argparse.ArgumentParser]") -> None:
    p = add_command(sub, "presets", "list the presets, their parameters in SI units, and what each parameter "
                    "means (the names --param takes)", "gyrocore presets --json", run)
    p.add_argument("--json", action="store_true",
                   help="print JSON: the recommended preset, each preset's parameters, and each parameter's meaning")


def run(args: argparse.Namespace) -> int:
    params = {name: preset_params(name) for name in preset_names()}
    # the values alone (threshold=0.0052...) said neither what a name means nor its unit
    meanings = parameters()
    if args.json:
        print_json({"recommended": recommended_preset(), "presets": params, "parameters": meanings})
        return 0
    for name, p in params.items():
        mark = " (recommended)" if name == recommended_preset() else ""
        print(f"{name}{mark}: " + ", ".join(f"{k}={v}" for k, v in p.items()))
    print(f"\nparameters (SI units; change one with --param NAME=VALUE; {', '.join(_RATE_PARAMETERS)} also as "
          "NAME_dps=VALUE in deg/s):")
    width = max(map(len, meanings))
    for key, meaning in meanings.items():
        print(f"  {key:<{width}}  {meaning}")
    return 0
