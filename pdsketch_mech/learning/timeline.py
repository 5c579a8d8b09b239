"""The segmentation as a timeline: text rows (for the terminal) and a picture (key frames
above a time axis with the hand's mode, each object's supports and the basis steps)."""
from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np

from .extract import Extraction
from .segmentation import Segment


def segment_step_labels(extraction: Extraction) -> List[str]:
    """For each segment: the steps whose contact change starts it, or which step its motion
    is folded into (pure motion changes no contact; see `steps.py`)."""
    steps = extraction.explanation.steps
    names = extraction.names
    labels = []
    for i, s in enumerate(extraction.segmentation.segments):
        here = [(k, st) for k, st in enumerate(steps, 1) if st.segment == i]
        text = ", ".join(f"{k} {st.text(names)}" for k, st in here)
        if not s.mode.pushed:
            motion = "transit" if s.mode.held is None else "move"
            later = next((k for k, st in enumerate(steps, 1) if st.segment > i), None)
            tail = f"{motion} -> in step {later}" if later else f"{motion} (after the last step)"
            text = f"{text}; then {tail}" if text else tail
        labels.append(text)
    return labels


def _supports(extraction: Extraction, frame: int, held: Optional[int]) -> str:
    names = extraction.names
    g = extraction.segmentation.graphs[frame]
    on = [f"{names[x]} on {names[y]}" for x, y in sorted(g.support) if x != held]
    touch = [f"{names[a]}-{names[b]}" for a, b in sorted(g.touching)
             if (a, b) not in g.support and (b, a) not in g.support and held not in (a, b)]
    return ", ".join(on + [f"{t} touch" for t in touch]) or "-"


def timeline_rows(extraction: Extraction) -> List[Tuple[str, str, str, str, str]]:
    seg = extraction.segmentation
    names = extraction.names
    rows = []
    for s, label in zip(seg.segments, segment_step_labels(extraction)):
        rows.append((f"{s.start}-{s.end}", f"{seg.time(s.start):5.2f}-{seg.time(s.end):5.2f}",
                     s.mode.describe(names), _supports(extraction, s.end, s.mode.held), label))
    return rows


def timeline_text(extraction: Extraction) -> str:
    """The timeline as aligned text: frames, time, the robot's mode, supports at the segment's
    end, and the basis step."""
    header = ("frames", "time (s)", "contact mode", "supports at the end", "basis step")
    rows = [header] + timeline_rows(extraction)
    widths = [max(len(r[i]) for r in rows) for i in range(4)]
    lines = ["  ".join(r[i].ljust(widths[i]) for i in range(4)) + "  " + r[4] for r in rows]
    return "\n".join(lines)


def key_frames(extraction: Extraction, count: int = 6) -> List[int]:
    """One frame per segment (its middle; the last frame for the last segment), at most `count`."""
    segs: Sequence[Segment] = extraction.segmentation.segments
    frames = [(s.start + s.end) // 2 for s in segs[:-1]] + [segs[-1].end]
    if len(frames) > count:
        pick = np.linspace(0, len(frames) - 1, count).round().astype(int)
        frames = [frames[i] for i in sorted(set(pick))]
    return frames


def render_timeline(extraction: Extraction, path: str, frames: Sequence[int], images: Sequence[np.ndarray]) -> None:
    """Save a PNG: `images` (rendered at `frames`) in a row, the timeline under them."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    seg = extraction.segmentation
    names = extraction.names
    t = seg.recording.arrays["time"]
    movable = [o for o in seg.bodies.objects if o not in seg.bodies.fixed]
    n_img = max(1, len(images))
    fig = plt.figure(figsize=(max(12.0, 2.6 * n_img), 6.6), dpi=100)
    grid = fig.add_gridspec(2, n_img, height_ratios=[1.0, 1.6], hspace=0.12, wspace=0.04)
    letters = "ABCDEFGHIJKL"
    for k, (frame, image) in enumerate(zip(frames, images)):
        ax = fig.add_subplot(grid[0, k])
        ax.imshow(image)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"{letters[k]}  t = {t[frame]:.1f} s", fontsize=10)
    ax = fig.add_subplot(grid[1, :])
    colors = {o: plt.cm.tab10(i % 10) for i, o in enumerate(seg.bodies.objects)}
    rows = ["hand"] + [f"{names[o]} on" for o in movable] + ["steps"]
    y = {r: len(rows) - 1 - i for i, r in enumerate(rows)}
    for s in seg.segments:
        x0, x1 = t[s.start], t[s.end]
        if s.mode.held is not None:
            ax.barh(y["hand"], x1 - x0, left=x0, height=0.6, color=colors[s.mode.held], edgecolor="black", lw=0.5)
            label = f"holds {names[s.mode.held]}"
        else:
            ax.barh(y["hand"], x1 - x0, left=x0, height=0.6, color="#dddddd", edgecolor="black", lw=0.5)
            label = "free"
        if s.mode.pushed:
            ax.barh(y["hand"], x1 - x0, left=x0, height=0.6, color="none", hatch="///", edgecolor="black", lw=0.5)
            label = s.mode.describe(names)
        ax.text((x0 + x1) / 2, y["hand"], label, ha="center", va="center", fontsize=8, clip_on=True,
                bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8))
    for o in movable:
        _support_bars(ax, extraction, o, y[f"{names[o]} on"], colors, t)
    for k, st in enumerate(extraction.explanation.steps, 1):
        x = t[st.frame]
        ax.axvline(x, color="black", lw=0.8, ls="--", alpha=0.6)
        ax.text(x, y["steps"] + 0.05 * (k % 2), f" {k}. {st.text(names)}", fontsize=8, va="center",
                rotation=0, ha="left")
    for k, frame in enumerate(frames):
        ax.plot([t[frame]], [len(rows) - 0.35], marker="v", color="black")
        ax.text(t[frame], len(rows) - 0.2, letters[k], ha="center", fontsize=9)
    ax.set_yticks([y[r] for r in rows])
    ax.set_yticklabels(rows)
    ax.set_ylim(-0.6, len(rows))
    ax.set_xlim(0, t[-1] * 1.12 if t[-1] > 0 else 1)
    ax.set_xlabel("time (s)")
    ax.set_title(f"{extraction.name}: contact modes and basis steps "
                 f"(hatched: a push; thin bars in an object's row: what supports it)", fontsize=10)
    fig.savefig(path, bbox_inches="tight")
    plt.close(fig)


def _support_bars(ax, extraction: Extraction, obj: int, row: float, colors, t) -> None:
    """Runs of what supports `obj` (nothing while held), each in its supporter's colour."""
    seg = extraction.segmentation
    names = extraction.names
    values = [tuple(seg.supports_of(obj, f)) for f in range(seg.recording.frames)]
    start = 0
    for f in range(1, len(values) + 1):
        if f == len(values) or values[f] != values[start]:
            if values[start]:
                x0, x1 = t[start], t[f - 1]
                sup = values[start][0]
                ax.barh(row, x1 - x0, left=x0, height=0.35, color=colors.get(sup, "#999999"), alpha=0.55,
                        edgecolor="black", lw=0.4)
                ax.text((x0 + x1) / 2, row, " + ".join(names[s] for s in values[start]), ha="center",
                        va="center", fontsize=7, clip_on=True)
            start = f
