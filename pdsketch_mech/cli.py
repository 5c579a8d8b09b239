"""Helpers shared by the command-line entry points (`python -m pdsketch_mech.X`)."""
from __future__ import annotations

import json
import os
import sys
from typing import Any, Callable, Dict, List

from .lang.errors import PddlError, PddlWarning

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


def print_warning(warning: PddlWarning) -> None:
    """The one-line `FILE:LINE:COL: warning: ...` on stderr."""
    print(warning, file=sys.stderr)


def run(main: Callable[[], int]) -> int:
    """Run a command's `main`, turning a closed pipe (`| head`) or Ctrl-C into a quiet exit."""
    try:
        return main()
    except BrokenPipeError:
        # Python would complain again when flushing stdout at exit; point it at /dev/null.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


def write_plan_json(path: str, status: str, reason: str, time_s: float, seed: int,
                    plan: List[Dict[str, Any]], stats: Dict[str, Any]) -> None:
    """The `plan --json` document of DESIGN.md, for classical and manipulation plans alike."""
    document = {"status": status, "reason": reason, "time_s": round(time_s, 6), "seed": seed,
                "plan": plan, "stats": stats}
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(document, handle, indent=1)
        handle.write("\n")
