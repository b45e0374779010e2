"""``python -m gyrocore``: the ``gyrocore`` command, as ``python -m gyrocore.cli`` runs it."""

from .cli import run

run()
