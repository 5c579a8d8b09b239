"""Edits of a domain file's text that keep everything else as the user wrote it.

`learn train` names its checkpoint in the fragment (`:sampler "NAME.samplers.safetensors"`).
Re-rendering the parsed domain (writer.py) would drop the user's comments inside the
definition and re-indent it; these edits change only the `:sampler` clause.
"""
from __future__ import annotations

from typing import Optional, Tuple

from .nodes import Mechanism
from .writer import string_literal


def _offset(text: str, line: int, col: int) -> int:
    """The 0-based offset of a 1-based (line, column) in `text`."""
    starts = [0]
    for k, char in enumerate(text):
        if char == "\n":
            starts.append(k + 1)
    return starts[line - 1] + col - 1


def _form_end(text: str, start: int) -> int:
    """The offset of the parenthesis that closes the form opening at `start`, skipping
    comments (`;` to the end of the line) and strings."""
    depth, k = 0, start
    while k < len(text):
        char = text[k]
        if char == ";":
            k = text.find("\n", k)
            if k < 0:
                break
        elif char == '"':
            k = text.index('"', k + 1)
        elif char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
            if depth == 0:
                return k
        k += 1
    raise ValueError("unbalanced parentheses")


def _sampler_string(text: str, start: int, end: int) -> Optional[Tuple[int, int]]:
    """(start, end) of the string after the form's own `:sampler` keyword (not one in a
    nested form or a comment), or None."""
    depth, k = 0, start
    while k < end:
        char = text[k]
        if char == ";":
            k = text.find("\n", k)
        elif char == '"':
            k = text.index('"', k + 1)
        elif char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
        elif depth == 1 and text.startswith(":sampler", k) and not (text[k + 8:k + 9].isalnum()
                                                                    or text[k + 8:k + 9] in "-_"):
            first = text.index('"', k)
            return first, text.index('"', first + 1) + 1
        k += 1
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
