"""Every reproduction of the papers' experiments in turn (about 15 seconds): tables to the
terminal, figures (PNG) into the folder given as the first argument (default: the current folder).
The same as ``gyrocore reproduce --out OUT_DIR``; figures there already are refused unless
``--overwrite`` follows (the other examples write the same figures into the current folder).

    python examples/reproduce_all.py [OUT_DIR] [--overwrite]
"""

import sys

from gyrocore.cli import main

if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--overwrite"]
    overwrite = ["--overwrite"] if "--overwrite" in sys.argv[1:] else []
    sys.exit(main(["reproduce", "--out", args[0] if args else ".", *overwrite]))
