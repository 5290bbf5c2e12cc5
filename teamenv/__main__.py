"""``python -m teamenv``: the same as the ``teamenv`` console script."""

import sys

from teamenv.cli import main

sys.exit(main())
