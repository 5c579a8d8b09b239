"""Edits of a domain file's text that keep everything else as the user wrote it.

`learn train` names its checkpoint in the fragment (`:sampler "NAME.samplers.safetensors"`).
Re-rendering the parsed domain (writer.py) would drop the user's comments inside the
definition and re-indent it; these edits change only the `:sampler` clause.
"""
from __future__ import annotations

from typing import Iterator, Optional, Tuple

from .nodes import Mechanism
from .writer import string_literal


def _offset(text: str, line: int, col: int) -> int:
    """The 0-based offset of a 1-based (line, column) in `text`."""
    starts = [0]
    for k, char in enumerate(text):
        if char == "\n":
            starts.append(k + 1)
    return starts[line - 1] + col - 1


def _scan(text: str, start: int) -> Iterator[Tuple[int, int]]:
    """(offset, depth) of each character from `start` outside comments (`;` to the end of
    the line) and strings, depth counting the parentheses open before it (an opening one
    counts itself)."""
    depth, k = 0, start
    while 0 <= k < len(text):
        char = text[k]
        if char == ";":
            k = text.find("\n", k)
            continue
        if char == '"':
            k = text.index('"', k + 1) + 1
            continue
        depth += (char == "(") - (char == ")")
        yield k, depth + (char == ")")
        k += 1


def _form_end(text: str, start: int) -> int:
    """The offset of the parenthesis that closes the form opening at `start`."""
    for k, depth in _scan(text, start):
        if text[k] == ")" and depth == 1:
            return k
    raise ValueError("unbalanced parentheses")


def _sampler_string(text: str, start: int, end: int) -> Optional[Tuple[int, int]]:
    """(start, end) of the string after the form's own `:sampler` keyword (not one in a
    nested form or a comment), or None."""
    for k, depth in _scan(text, start):
        if k >= end:
            break
        after = text[k + 8:k + 9]
        if depth == 1 and text.startswith(":sampler", k) and not (after.isalnum() or after in "-_"):
            first = text.index('"', k)
            return first, text.index('"', first + 1) + 1
    return None


def set_mechanism_sampler(text: str, mechanism: Mechanism, sampler: str) -> str:
    """`text` (the file `mechanism` was parsed from) with the mechanism's `:sampler` naming
    `sampler`: its string replaced, or the clause added before the mechanism's closing
    parenthesis."""
    start = _offset(text, mechanism.loc.line, mechanism.loc.col)
    end = _form_end(text, start)
    found = _sampler_string(text, start, end)
    if found is not None:
        return text[:found[0]] + string_literal(sampler) + text[found[1]:]
    return text[:end] + f"\n    :sampler {string_literal(sampler)}" + text[end:]
