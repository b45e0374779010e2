"""Hong & Park Table 1: pure integration, self-calibration, threshold filter and both on
simulated XV3500 robot runs, and Figure 10.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/hong_table_1.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("hong-table-1", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
