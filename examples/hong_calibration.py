"""Hong & Park section 3.1: least-squares self-calibration with a rate and a heading
reference on a gyro with s = -10 %, b = 0.1 rad/s, and Figures 6 and 7.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/hong_calibration.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("hong-calibration", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
