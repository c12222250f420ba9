"""What every output module shares: files written whole or not at all, one CSV writer and the plot styling
(file-only backend,
branches drawn stable solid / unstable dashed with their special points labelled)."""

from slosh_bif.report.files import replaced_atomically, write_text_atomically
from slosh_bif.report.plotting import plot_branch, pyplot, save_figure
from slosh_bif.report.tables import write_rows

__all__ = [
    "write_rows",
    "pyplot",
    "save_figure",
    "plot_branch",
    "replaced_atomically",
    "write_text_atomically",
]
