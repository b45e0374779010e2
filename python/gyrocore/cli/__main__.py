"""``python -m gyrocore.cli``."""

import sys

from . import main

sys.exit(main())
