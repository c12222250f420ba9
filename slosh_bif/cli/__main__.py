"""``python -m slosh_bif.cli``: the same as the ``slosh-bif`` command."""

from slosh_bif.cli import run

if __name__ == "__main__":  # not on import (the API reference imports every module)
    run()
