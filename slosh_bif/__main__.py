"""``python -m slosh_bif``: the same as the ``slosh-bif`` command."""

import sys

from slosh_bif.cli import main

sys.exit(main())
