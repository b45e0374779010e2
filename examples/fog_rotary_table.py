"""FOG section 3: the scale factor of the fibre-optic gyro against temperature on a
rotary table (eq 5, Figure 3) and the turn errors after the correction of eq 6 (Figure 6).

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/fog_rotary_table.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("fog-rotary-table", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
