"""Seeded mutations of `.pddl` files for the hostile-input fuzzer (`bench fuzz`): token,
line and byte edits, deep nesting, special numbers and other encodings, and growths (up to
120,000 objects, 300,000 facts, 1.2 M predicate declarations). Each mutation takes the
file's bytes and a `random.Random` and returns new bytes."""
from __future__ import annotations

import random
import re
from typing import Callable, Dict, List, Tuple

_TOKEN = re.compile(rb'\(|\)|"[^"\n]*"|;[^\n]*|[^\s()";]+')
_NUMBER = re.compile(rb"(?<![\w.?-])[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?(?![\w.])")
_ATOM = re.compile(rb"\(\s*[A-Za-z][\w-]*[\s)]")

SPECIAL_NUMBERS = [b"1e400", b"-1e400", b"1" + b"0" * 5000, b"0." + b"0" * 5000 + b"1", b"1e-300", b"0",
                   b"-0", b"nan", b"inf", b"1e308", b"4e-324", b"-1", b"1e999999999999"]
VOCABULARY = [b"(", b")", b"-", b"and", b"or", b"not", b"imply", b"forall", b"exists", b"when", b"either",
              b"define", b"domain", b"problem", b":action", b":parameters", b":precondition", b":effect",
              b":types", b":objects", b":init", b":goal", b":scene", b":stream", b":mechanism", b":extends",
              b":requirements", b":strips", b":typing", b":asset", b":position", b":rpy", b":quat", b":scale",
              b":mass", b":friction", b":on", b":fixed", b":color", b"?x", b"?", b"object", b"=", b'"',
              b'""', b'"block/0"', b"item", b"table", b";", b"#grasp1", b"\xe2\x80\xae", b"\x1b[31m"]
RAW_BYTES = [b"\xff", b"\x00", b"\x1b", b"\x1b[2J", b"\r", b"\t", b"\x0b", b"\xc3", b"\xe2\x80\xa8",
             b"\xf0\x9f\x98\x80", b"\xed\xa0\x80", b"\xc0\xaf", b"\x7f", b"\xc2\x85"]
NESTING = [50, 400, 499, 501, 2000, 20000]
WRAPPERS = [(b"(not ", b")"), (b"(and ", b")"), (b"(or ", b")"), (b"(exists (?v) ", b")"),
            (b"(imply (and) ", b")"), (b"(forall (?w) ", b")")]

Mutation = Callable[[bytes, random.Random], bytes]


def _spans(data: bytes, pattern: re.Pattern = _TOKEN) -> List[Tuple[int, int]]:
    return [m.span() for m in pattern.finditer(data)]


def delete_token(data: bytes, rng: random.Random) -> bytes:
    spans = _spans(data)
    if not spans:
        return data
    a, b = rng.choice(spans)
    return data[:a] + data[b:]


def duplicate_token(data: bytes, rng: random.Random) -> bytes:
    spans = _spans(data)
    if not spans:
        return data
    a, b = rng.choice(spans)
    return data[:b] + b" " + data[a:b] + data[b:]


def swap_tokens(data: bytes, rng: random.Random) -> bytes:
    spans = _spans(data)
    if len(spans) < 2:
        return data
    i = rng.randrange(len(spans) - 1)
    (a, b), (c, d) = spans[i], spans[i + 1]
    return data[:a] + data[c:d] + data[b:c] + data[a:b] + data[d:]


def replace_token(data: bytes, rng: random.Random) -> bytes:
    spans = _spans(data)
    if not spans:
        return data
    a, b = rng.choice(spans)
    words = [data[x:y] for x, y in spans if data[x:y][:1] not in b'(;)"']
    choice = rng.choice(VOCABULARY + (words[:200] or [b"x"]))
    return data[:a] + choice + data[b:]


def _lines(data: bytes) -> List[bytes]:
    return data.split(b"\n")


def delete_line(data: bytes, rng: random.Random) -> bytes:
    lines = _lines(data)
    del lines[rng.randrange(len(lines))]
    return b"\n".join(lines)


def duplicate_line(data: bytes, rng: random.Random) -> bytes:
    lines = _lines(data)
    i = rng.randrange(len(lines))
    lines.insert(i, lines[i])
    return b"\n".join(lines)


def swap_lines(data: bytes, rng: random.Random) -> bytes:
    lines = _lines(data)
    if len(lines) < 2:
        return data
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def flip_byte(data: bytes, rng: random.Random) -> bytes:
    if not data:
        return data
    i = rng.randrange(len(data))
    return data[:i] + bytes([data[i] ^ (1 << rng.randrange(8))]) + data[i + 1:]


def insert_bytes(data: bytes, rng: random.Random) -> bytes:
    i = rng.randrange(len(data) + 1)
    chunk = rng.choice(RAW_BYTES) if rng.random() < 0.7 else bytes(rng.randrange(256) for _ in range(rng.randint(1, 4)))
    return data[:i] + chunk + data[i:]


def truncate(data: bytes, rng: random.Random) -> bytes:
    return data[:rng.randrange(len(data) + 1)]


def deep_nesting(data: bytes, rng: random.Random) -> bytes:
    """Wrap an atom in N nested formulas (N from 50 to 20,000), or open N parentheses."""
    atoms = _spans(data, _ATOM)
    depth = rng.choice(NESTING)
    if not atoms or rng.random() < 0.15:
        i = rng.randrange(len(data) + 1)
        return data[:i] + b"(" * depth + data[i:]
    start = rng.choice(atoms)[0]
    end = _matching(data, start)
    if end is None:
        return data
    opening, closing = rng.choice(WRAPPERS)
    return data[:start] + opening * depth + data[start:end + 1] + closing * depth + data[end + 1:]


def _matching(data: bytes, start: int):
    depth = 0
    for i in range(start, len(data)):
        depth += {40: 1, 41: -1}.get(data[i], 0)
        if depth == 0:
            return i
    return None


def special_number(data: bytes, rng: random.Random) -> bytes:
    """Replace a number (a scene value, most often) with an extreme one, or add one."""
    spans = _spans(data, _NUMBER)
    if not spans:
        i = rng.randrange(len(data) + 1)
        return data[:i] + b" " + rng.choice(SPECIAL_NUMBERS) + b" " + data[i:]
    a, b = rng.choice(spans)
    return data[:a] + rng.choice(SPECIAL_NUMBERS) + data[b:]


def encoding(data: bytes, rng: random.Random) -> bytes:
    """The same text in another encoding or with other line endings."""
    text = data.decode("utf-8", errors="replace")
    kind = rng.randrange(6)
    if kind == 0:
        return text.encode("utf-16")
    if kind == 1:
        i = rng.randrange(len(text) + 1)
        return (text[:i] + "é" + text[i:]).encode("latin-1", errors="replace")
    if kind == 2:
        return b"\xef\xbb\xbf" + data
    if kind == 3:
        return data.replace(b"\n", b"\r\n")
    if kind == 4:
        return data.replace(b"\n", b"\r")
    return text.encode("utf-32")


OBJECT_COUNTS = [100, 5000, 120_000]
FACT_COUNTS = [1000, 30_000, 300_000]
PREDICATE_COUNTS = [1000, 100_000, 1_200_000]
_SECTION = re.compile(rb"\(\s*(:objects|:constants|:init|:predicates)\b", re.IGNORECASE)
_FIRST_ATOM = re.compile(rb"\(\s*[A-Za-z][\w-]*(?:\s+[A-Za-z][\w-]*)*\s*\)")


def _after_section(data: bytes, names: Tuple[bytes, ...], rng: random.Random,
                   counts: List[int]) -> Tuple[int, int]:
    """Where to insert into the first of the sections `names` (just after its keyword), and
    how many items; anywhere when the file has none of them, but then not the largest count:
    elsewhere (in a formula, a scene) items are read token by token, about 20 us and 1 kB a
    token (docs/limits.md), and a million would only measure that again."""
    for match in _SECTION.finditer(data):
        if match.group(1).lower() in names:
            return match.end(), rng.choice(counts)
    return rng.randrange(len(data) + 1), rng.choice(counts[:-1])


def many_objects(data: bytes, rng: random.Random) -> bytes:
    """Up to 120,000 more names in :objects (or :constants), typed as the section's first."""
    i, count = _after_section(data, (b":objects", b":constants"), rng, OBJECT_COUNTS)
    names = b" ".join(b"fz%d" % k for k in range(count))
    return data[:i] + b" " + names + b" " + data[i:]


def many_facts(data: bytes, rng: random.Random) -> bytes:
    """Up to 300,000 more facts in :init: copies of its first atom, or of one on new names."""
    i, count = _after_section(data, (b":init",), rng, FACT_COUNTS)
    atom = _FIRST_ATOM.search(data, i)
    if atom is not None and rng.random() < 0.5:
        facts = b" ".join([atom.group()] * count)
    else:
        facts = b" ".join(b"(fz-p fz%d fz%d)" % (k, k + 1) for k in range(count))
    return data[:i] + b"\n" + facts + b"\n" + data[i:]


def many_predicates(data: bytes, rng: random.Random) -> bytes:
    """Up to 1.2 M more declarations in :predicates: all `(p)`, or distinct ones."""
    i, count = _after_section(data, (b":predicates",), rng, PREDICATE_COUNTS)
    if rng.random() < 0.5:
        declarations = b" ".join([b"(p)"] * count)
    else:
        declarations = b" ".join(b"(fz%d ?x ?y)" % k for k in range(count))
    return data[:i] + b"\n" + declarations + b"\n" + data[i:]


GROWTHS: Dict[str, Mutation] = {"many-objects": many_objects, "many-facts": many_facts,
                                "many-predicates": many_predicates}

MUTATIONS: Dict[str, Mutation] = {
    "delete-token": delete_token, "duplicate-token": duplicate_token, "swap-tokens": swap_tokens,
    "replace-token": replace_token, "delete-line": delete_line, "duplicate-line": duplicate_line,
    "swap-lines": swap_lines, "flip-byte": flip_byte, "insert-bytes": insert_bytes, "truncate": truncate,
    "deep-nesting": deep_nesting, "special-number": special_number, "encoding": encoding, **GROWTHS,
}


def mutate(data: bytes, rng: random.Random, grow: bool = True) -> Tuple[bytes, List[str]]:
    """One to three random mutations of `data`, and their names; without the growths
    (`GROWTHS`) unless `grow`."""
    kinds = list(MUTATIONS) if grow else [k for k in MUTATIONS if k not in GROWTHS]
    names = [rng.choice(kinds) for _ in range(rng.choice((1, 1, 2, 3)))]
    for name in names:
        data = MUTATIONS[name](data, rng)
    return data, names
