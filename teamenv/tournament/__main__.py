"""``python -m teamenv.tournament ...``: the same as ``teamenv tournament ...``."""

import sys

from teamenv.cli import main

sys.exit(main(["tournament", *sys.argv[1:]]))
