"""FOG section 4.1: return orientation errors of the 4x4 m bi-directional square path
(Figure 5), with the eq 6 correction and without it.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/fog_square_path.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("fog-square-path", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
