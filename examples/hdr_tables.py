"""HDR Tables II and IV: fourteen simulated drives with one parameter set, E_psi and
NE_psi without and with HDR, and the improvement factors beside the paper's 9.2x and 6.9x.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/hdr_tables.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("hdr-tables", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
