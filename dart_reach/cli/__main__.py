"""``python -m dart_reach.cli``: the same as ``dart-reach``."""

import sys

from . import main

sys.exit(main())
