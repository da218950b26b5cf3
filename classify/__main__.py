"""``python -m classify`` runs the ``closedchain`` command."""

import sys

from .cli import main

sys.exit(main())
