"""HDR Figures 3 and 5: -I against the simulated drift around 20 s of curving at
2 deg/s, without and with the repetition attenuator.

Prints the paper's values beside ours and writes the figure (PNG) into the folder given as the
first argument (default: the current folder).

    python examples/hdr_figures.py [OUT_DIR]
"""

import sys

from gyrocore.paper import reproduce

if __name__ == "__main__":
    reproduce("hdr-figures", out_dir=sys.argv[1] if len(sys.argv) > 1 else ".")
