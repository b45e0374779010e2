"""Every reproduction of the papers' experiments in turn (about half a minute): tables to the
terminal, figures (PNG) into the folder given as the first argument (default: the current folder).

    python examples/reproduce_all.py [OUT_DIR]
"""

import sys

from gyrocore.paper import REPRODUCTIONS, reproduce

if __name__ == "__main__":
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
    for name in REPRODUCTIONS:
        reproduce(name, out_dir=out_dir)
        print()
