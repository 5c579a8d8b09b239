"""Lark parse failures -> one-line `PddlError`s: what was found, what was expected (exactly,
by replaying the parser), a did-you-mean for misspelt keywords, and where an unclosed
parenthesis was opened."""
from __future__ import annotations

import re
from typing import Iterable, List, Sequence, Tuple

from lark.exceptions import UnexpectedEOF, UnexpectedInput, UnexpectedToken
from lark.lexer import TerminalDef

from .errors import PddlError, did_you_mean
from .nodes import Loc

# How terminals are named in messages ("expected ')' or a variable").
_TERMINAL_WORDS = {
    "NAME": "a name", "NAME_RUN": "a name", "VARIABLE": "a variable", "REQUIREMENT": "a requirement such as :strips",
    "KEYWORD": "a property such as :asset", "NUMBER": "a number", "STRING": 'a "string"',
    "$END": "end of file", "<END-OF-FILE>": "end of file",
    "ATOM_RUN": "'('", "PREDICATE_RUN": "'('",  # runs of items: each starts with one
}


def _describe_terminal(name: str, terminals: Sequence[TerminalDef]) -> str:
    if name in _TERMINAL_WORDS:
        return _TERMINAL_WORDS[name]
    for terminal in terminals:
        if terminal.name == name and terminal.pattern.type == "str":
            return f"'{terminal.pattern.value}'"
    return name.lower()


def _expected_words(names: Iterable[str], terminals: Sequence[TerminalDef]) -> List[str]:
    return sorted({_describe_terminal(n, terminals) for n in names})


def _one_of(words: List[str]) -> str:
    if len(words) > 12:
        return "one of " + ", ".join(words[:12]) + f", ... ({len(words) - 12} more)"
    return ("one of " + ", ".join(words)) if len(words) > 1 else (words[0] if words else "nothing")


def _open_parens(text: str) -> List[int]:
    """Offsets of the '(' still open at the end of `text` (comments and strings skipped)."""
    stack: List[int] = []
    in_comment = in_string = False
    for index, char in enumerate(text):
        if in_comment:
            in_comment = char != "\n"
        elif in_string:
            in_string = char != '"'
        elif char == ";":
            in_comment = True
        elif char == '"':
            in_string = True
        elif char == "(":
            stack.append(index)
        elif char == ")" and stack:
            stack.pop()
    return stack


def _line_col(text: str, offset: int) -> Tuple[int, int]:
    return text.count("\n", 0, offset) + 1, offset - (text.rfind("\n", 0, offset) + 1) + 1


def syntax_error(exc: UnexpectedInput, text: str, file: str, terminals: Sequence[TerminalDef]) -> PddlError:
    """One located, readable error for a Lark parse failure."""
    at_end = isinstance(exc, UnexpectedEOF) or (
        isinstance(exc, UnexpectedToken) and exc.token.type == "$END")
    if at_end:
        opened = _open_parens(text)
        where = ""
        if opened:
            line, col = _line_col(text, opened[-1])
            where = f"; the '(' at line {line}, column {col} is never closed"
        line, col = _line_col(text, len(text.rstrip("\n")))
        return PddlError(f"unexpected end of file{where}", Loc(file, line, col))

    loc = Loc(file, exc.line, exc.column)
    # LALR merges look-ahead sets across states; accepts() replays the parse per terminal,
    # so an action's error does not also offer a stream's ':inputs'.
    parser = getattr(exc, "interactive_parser", None)
    if isinstance(exc, UnexpectedToken):
        expected, word, kind = exc.expected, str(exc.token), exc.token.type
        if kind == "NAME_RUN":  # several names lexed as one token: the first is unexpected
            word, kind = word.split()[0], "NAME"
        elif kind in ("ATOM_RUN", "PREDICATE_RUN"):  # several items as one token: the first '('
            word, kind = "(", None
    else:
        expected, kind = exc.allowed, None
        word = re.match(r"[^\s()]*", text[exc.pos_in_stream:]).group(0) or text[exc.pos_in_stream]
    if word.startswith('"'):
        return PddlError("unterminated string: a string must end on the line it starts", loc)
    if word.lower() == ":functions":
        return PddlError("numeric fluents (:functions) are not supported", loc)
    if set(expected) <= {"$END", "<END-OF-FILE>"}:
        return PddlError(f"unexpected '{word}' after the end of the definition", loc)

    words = _expected_words(parser.accepts() if parser is not None else expected, terminals)
    hint = did_you_mean(word.lower(), [w.strip("'") for w in words if w.startswith("'")])
    shown = {"NAME": f"name '{word}'", "VARIABLE": f"variable '{word}'"}.get(kind, f"'{word}'")
    return PddlError(f"unexpected {shown}{hint}; expected {_one_of(words)}", loc)
