"""``python -m texsynth``: the same as the ``texsynth`` command."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
