"""Runs of flat, parenthesised items lexed as one token and split here: ground atoms in
`:init` (`ATOM_RUN`) and predicate declarations in `:predicates` (`PREDICATE_RUN`).

The parser's cost is per token (a 300,000-fact `:init` is 1.5 M tokens); these sections are
mostly long lists of the simplest items, which a regular expression splits many times
faster. Anything else (a variable in an atom, an `either` type) does not match the run's
pattern and goes through the grammar as before. Every node keeps its exact line and column.
"""
from __future__ import annotations

import re
import sys
from typing import Iterator, List, Tuple

from .nodes import Atom, Const, Loc, Predicate, TypedName

_ITEM = re.compile(r"\([ \t\f\r\n]*([^ \t\f\r\n()]+)([^()]*)\)")  # the grammar's whitespace only
_WORD = re.compile(r"[^ \t\f\r\n()]+")

Words = List[Tuple[str, Loc]]


def _items(file: str, text: str, line: int, column: int) -> Iterator[Tuple[str, Loc, Words]]:
    """Each `(name word ...)` of a run: its name, location and other words with theirs.
    One tight loop: this is the inner loop of reading a million-item section; a generator,
    so that only the nodes built from the items stay in memory, not the items too."""
    line_start = 1 - column  # the offset that is column 1 of the current line
    newline = text.find("\n")
    for match in _ITEM.finditer(text):
        offset = match.start()
        if newline != -1 and newline < offset:
            line += text.count("\n", newline, offset)
            line_start = text.rfind("\n", newline, offset) + 1
            newline = text.find("\n", offset)
        column = offset - line_start + 1
        loc = Loc(file, line, column)
        words: Words = []
        rest = match.group(2)
        if not rest or rest.isspace():
            pass
        elif newline == -1 or newline > match.end():  # the item is on one line: no line to track
            first, position = column + match.start(2) - offset, 0
            for word in _WORD.findall(rest):
                position = rest.find(word, position)
                words.append((word, Loc(file, line, first + position)))
                position += len(word)
        else:
            for word in _WORD.finditer(text, match.start(2), match.end(2)):
                offset = word.start()
                if newline != -1 and newline < offset:
                    line += text.count("\n", newline, offset)
                    line_start = text.rfind("\n", newline, offset) + 1
                    newline = text.find("\n", offset)
                words.append((word.group(), Loc(file, line, offset - line_start + 1)))
        yield match.group(1), loc, words


def split_atoms(file: str, text: str, line: int, column: int) -> List[Atom]:
    """An `ATOM_RUN` token -> its ground atoms."""
    return [Atom(sys.intern(name.lower()), tuple([Const(arg.lower(), at) for arg, at in args]), loc)
            for name, loc, args in _items(file, text, line, column)]


def split_predicates(file: str, text: str, line: int, column: int) -> List[Predicate]:
    """A `PREDICATE_RUN` token -> its declarations (`(p ?x ?y - t ?z)`)."""
    out = []
    for name, loc, words in _items(file, text, line, column):
        params: List[TypedName] = []
        pending: Words = []
        expect_type = False
        for word, at in words:
            if word == "-":
                expect_type = True
            elif expect_type:
                type_ = sys.intern(word.lower())
                params.extend(TypedName(sys.intern(var.lower()), type_, var_loc) for var, var_loc in pending)
                pending, expect_type = [], False
            else:
                pending.append((word, at))
        params.extend(TypedName(sys.intern(var.lower()), "object", var_loc) for var, var_loc in pending)
        out.append(Predicate(name.lower(), tuple(params), loc))
    return out
