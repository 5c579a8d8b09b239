"""Progress bars for long work (self-play, training, benchmarks)."""
from __future__ import annotations

import sys
from typing import Any


def progress_bar(**options: Any) -> Any:
    """A tqdm bar on stderr. Into a log file (not a terminal) it redraws every LOG_INTERVAL
    seconds rather than ten times a second: each redraw is another copy of the bar there."""
    from tqdm import tqdm
    if not sys.stderr.isatty():
        options.setdefault("mininterval", LOG_INTERVAL)
    return tqdm(file=sys.stderr, **options)


LOG_INTERVAL = 30.0
