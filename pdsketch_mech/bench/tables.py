"""Benchmark tables as fixed-width text (the terminal) and as markdown (files, the README)."""
from __future__ import annotations

from typing import List


def render_text(header: List[str], cells: List[List[str]], lines: List[str]) -> str:
    """Fixed-width table (first column left-aligned, the rest right-aligned), then `lines`."""
    widths = [max(len(row[i]) for row in [header] + cells) for i in range(len(header))]

    def fmt(row: List[str]) -> str:
        return "  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths)))

    rule = "-" * len(fmt(header))
    return "\n".join([fmt(header), rule] + [fmt(row) for row in cells] + [rule] + lines) + "\n"


def render_markdown(header: List[str], cells: List[List[str]], lines: List[str]) -> str:
    """The same table and lines as markdown (a pipe table and a bullet list)."""
    rows = [header, [":---"] + ["---:"] * (len(header) - 1)] + cells
    return "\n".join("| " + " | ".join(row) + " |" for row in rows) + "\n\n" + "".join(f"- {x}\n" for x in lines)
