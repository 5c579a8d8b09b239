"""Errors in language files, reported as `FILE:LINE:COL: error: message`, and warnings
(accepted, but worth a look), reported as `FILE:LINE:COL: warning: message`.

Reports quote their input (names, words, file names), which may hold control characters
or terminal escape sequences: `escape` shows them as `\x1b`, so a report is always one
line of plain text."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

from .nodes import Loc


class PddlError(Exception):
    """A problem in a domain or problem file, with the place it was found.

    `str(error)` is the one-line report; `render()` may add the source line and a caret.
    """

    def __init__(self, message: str, loc: Optional[Loc] = None, file: Optional[str] = None):
        self.message = message
        self.loc = loc
        self.file = loc.file if loc is not None else file  # None: not about a file (an argument)
        super().__init__(str(self))

    def __str__(self) -> str:
        where = self.loc if self.loc is not None else self.file
        return escape(f"{where}: error: {self.message}" if where is not None else f"error: {self.message}")

    def render(self, source: Optional[str] = None) -> str:
        """The one-line report, followed by the offending source line and a caret if known."""
        line = str(self)
        if self.loc is None or source is None:
            return line
        lines = source.split("\n")
        if not 1 <= self.loc.line <= len(lines):
            return line
        text = lines[self.loc.line - 1].removesuffix("\r").replace("\t", " ")
        before = escape(text[:self.loc.col - 1])
        return f"{line}\n  {before}{escape(text[self.loc.col - 1:])}\n  {' ' * len(before)}^"


def escape(text: str) -> str:
    """`text` with every unprintable character (controls, escape sequences, line and
    paragraph separators, bidirectional overrides) shown as a Python escape: `\x1b`."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)


@dataclass(frozen=True)
class PddlWarning:
    """Something a file does that is accepted but probably not meant, with where it is."""

    message: str
    loc: Optional[Loc] = None
    file: str = "<input>"  # used when there is no `loc`

    def __str__(self) -> str:
        return escape(f"{self.loc if self.loc is not None else self.file}: warning: {self.message}")


def did_you_mean(name: str, candidates) -> str:
    """A ` (did you mean 'x'?)` suffix naming the closest candidate, or ''."""
    import difflib

    close = difflib.get_close_matches(name, sorted(candidates), n=1, cutoff=0.75)
    return f" (did you mean '{close[0]}'?)" if close else ""


def known_names(names: Sequence[str], limit: int = 12) -> str:
    """The names as a message lists them: in the order given, the first `limit` of them, then
    how many more."""
    names = list(names)
    shown = ", ".join(names[:limit])
    return shown + (f", ... ({len(names) - limit} more)" if len(names) > limit else "")
