"""Every reproduction of the papers' experiments in turn (under ten seconds): tables to the
terminal, figures (PNG) into the folder given as the first argument (default: the current folder).
The same as ``gyrocore reproduce --out OUT_DIR``.

    python examples/reproduce_all.py [OUT_DIR]
"""

import sys

from gyrocore.cli import main

if __name__ == "__main__":
    sys.exit(main(["reproduce", "--out", sys.argv[1] if len(sys.argv) > 1 else "."]))
