"""Checks on the raw text of a `.pddl` file before it is parsed: its encoding and how deeply
its parentheses nest. Both are reported at the offending line and column."""
from __future__ import annotations

import re
from itertools import accumulate

from .errors import PddlError
from .nodes import Loc

# Parentheses may nest this deep (the `define` counts). The parser itself has no limit, but
# type checking, normalisation and writing recurse over formulas, one Python frame a level.
MAX_NESTING = 500

_SKIPPED = re.compile(r';[^\n]*|"[^"\n]*"')   # comments and strings: their parentheses do not count
_NOT_PAREN = re.compile(r"[^()]+")
_STEP = {"(": 1, ")": -1}


def read_text(path: str) -> str:
    """The text of the file at `path`; an unreadable or non-UTF-8 file is a `PddlError`."""
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as exc:
        raise PddlError(f"cannot read file: {exc.strerror or exc}", file=path) from None
    return decode(data, path)


def decode(data: bytes, file: str) -> str:
    """UTF-8 bytes -> text (a leading byte-order mark is dropped); the first invalid byte is
    a located error."""
    try:
        return data.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as exc:
        start = data.rfind(b"\n", 0, exc.start) + 1
        column = len(data[start:exc.start].decode("utf-8", errors="replace")) + 1
        loc = Loc(file, data.count(b"\n", 0, exc.start) + 1, column)
        raise PddlError(f"not UTF-8: byte 0x{data[exc.start]:02x} cannot start or continue a "
                        "character; save the file as UTF-8", loc) from None


def check_nesting(text: str, file: str) -> None:
    """Reject parentheses nested deeper than `MAX_NESTING`, at the first one too deep."""
    parens = _NOT_PAREN.sub("", _SKIPPED.sub("", text))
    if not parens or max(accumulate(map(_STEP.__getitem__, parens))) <= MAX_NESTING:
        return
    depth = 0
    for match in re.finditer(r'[()]|;[^\n]*|"[^"\n]*"', text):
        char = match.group()
        depth += _STEP.get(char, 0)
        if depth > MAX_NESTING:
            offset = match.start()
            line = text.count("\n", 0, offset) + 1
            raise PddlError(f"parentheses nest deeper than {MAX_NESTING} levels", Loc(
                file, line, offset - text.rfind("\n", 0, offset)))
