"""``python -m slosh_bif.cli``: the same as the ``slosh-bif`` command."""

import sys

from slosh_bif.cli import main

if __name__ == "__main__":  # not on import (the API reference imports every module)
    sys.exit(main())
