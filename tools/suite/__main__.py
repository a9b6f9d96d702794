"""``python3 -m suite`` (with tools/ on PYTHONPATH): the runner's command line."""
import sys

from suite.cli import main

sys.exit(main(sys.argv[1:]))
