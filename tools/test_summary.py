#!/usr/bin/python3
"""Count what the last run of tools/test ran (its results folder, default .ws/test_results),
check it against what exists, print the closing line "total: N passed, N failed"."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from suite import summary  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

if __name__ == "__main__":
    sys.exit(summary.main(REPO, sys.argv[1] if len(sys.argv) > 1 else
                         os.path.join(REPO, ".ws", "test_results")))
