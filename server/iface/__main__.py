"""``python -m iface``: the same as the ``iface-lsp`` console script."""

import sys

from .cli import main

sys.exit(main())
