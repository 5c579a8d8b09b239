"""Helpers shared by the command-line entry points (`python -m pdsketch_mech.X`)."""
from __future__ import annotations

import sys

from .lang.errors import PddlError

EXIT_OK, EXIT_UNSOLVED, EXIT_BAD_INPUT = 0, 1, 2


def print_error(error: PddlError) -> None:
    """The one-line `FILE:LINE:COL: error: ...` on stderr; on a terminal also the source line."""
    source = None
    if sys.stderr.isatty() and error.loc is not None:
        try:
            with open(error.loc.file, encoding="utf-8") as handle:
                source = handle.read()
        except (OSError, UnicodeDecodeError):
            source = None
    print(error.render(source), file=sys.stderr)
