"""Hong & Park section 2.1: ARW and bias instability of the Epson XV3500 read from the
Allan deviation of simulated static logs (ten gyros, two runs each, as the paper), and Figure 2.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/hong_allan.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("hong-allan", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
