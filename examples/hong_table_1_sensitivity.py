"""Hong & Park Table 1 over a grid of gyro noise (noise bandwidth at the XV3500's ARW) and turn
size: which of the threshold filter and self-calibration gains more, and where the paper's order
of the methods holds.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/hong_table_1_sensitivity.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("hong-table-1-sensitivity", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
