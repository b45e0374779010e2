"""``python -m gyrocore.cli``."""

from . import run

run()
