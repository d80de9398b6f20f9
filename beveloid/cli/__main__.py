"""``python -m beveloid.cli``: the same as the ``beveloid`` script."""
import sys

from . import main

sys.exit(main())
