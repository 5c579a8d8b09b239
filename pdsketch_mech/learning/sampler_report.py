"""The learning report of a trained mechanism sampler: markdown and a PNG.

The PNG has three panels: the self-play success rate over episodes (running mean), the
training and validation loss of each parameter's classifier, and the validation ROC AUC
per parameter. The markdown repeats the figures with the data size and the command.
"""
from __future__ import annotations

import os
from typing import Dict, List, Sequence

import numpy as np

from ..util.files import atomic_file, write_text
from .sampler_training import ParamReport

FEW_ROWS = 50   # validation rows below which the report flags an AUC as resting on little


def success_curve(rows: Sequence[Dict[str, object]], window: int = 10) -> np.ndarray:
    """Running mean of episode success over the last `window` episodes, in episode order."""
    ok = np.array([float(bool(r["success"])) for r in sorted(rows, key=lambda r: int(r["episode"]))])
    if not len(ok):
        return ok
    cumulative = np.concatenate([[0.0], np.cumsum(ok)])
    idx = np.arange(1, len(ok) + 1)
    start = np.maximum(0, idx - window)
    return (cumulative[idx] - cumulative[start]) / (idx - start)


def _fmt(value, digits: int = 3) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def report_markdown(name: str, reports: Sequence[ParamReport], manifest: Dict[str, object], info: Dict[str, object],
                    png: str) -> str:
    totals = manifest.get("totals", {})
    selfplay_s = sum(float(r.get("seconds", 0.0)) for r in manifest.get("episodes", []))
    lines: List[str] = [
        f"# Learned samplers of mechanism `{name}`", "",
        f"Made by `{info['command']}`: {selfplay_s:.0f} s of self-play episodes (summed over workers), "
        f"{info['seconds_training']:.0f} s of training.", "",
        f"Self-play: {totals.get('episodes', 0)} episodes on the `{info['task']}` train split, "
        f"{totals.get('successes', 0)} succeeded; {totals.get('samples', 0)} proposals verified (values and rejected ones) "
        f"of every parameter, trajectories included, {totals.get('positives', 0)} of them in a successful plan. "
        "The table counts the parameters with a classifier only, after subsampling.", "",
        "| parameter | kind | rows (rejected proposals) | positives | validation rows (positives) | kept epoch "
        "| validation AUC | balanced accuracy | verification AUC |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in reports:
        auc = _fmt(r.auc) if not r.skipped else f"not trained: {r.skipped}"
        if not r.skipped and r.auc is not None and r.validation_rows < FEW_ROWS:
            auc += f" (only {r.validation_rows} rows)"   # a tiny run's AUC of 1.000 means little
        lines.append(f"| `{r.variable}` | {r.kind} | {r.rows} ({r.rejected}) | {r.positives} | {r.validation_rows} "
                     f"({r.validation_positives}) | {r.best_epoch or '-'} | {auc} | {_fmt(r.balanced_accuracy)} "
                     f"| {_fmt(r.verify_auc)} |")
    lines += ["", "A row is a proposal the generic sampler verified: a value, or one that failed verification "
              "(rejected proposals beyond 4 per value are subsampled and weighted). Validation AUC ranks the "
              "held-out proposals by the classifier's score (P(verifies) x P(used | verified)) against whether the "
              "successful plan used them; balanced accuracy calls a proposal used when both heads give even odds or "
              "better; verification AUC is the first head alone against verification's outcome. Validation holds "
              "out whole episodes (seeded); the weights of the epoch with the lowest validation loss are kept, so "
              "the validation figures are a little optimistic. '-': the held-out rows hold one class only.",
              ""]
    first = [r for r in reports if r.grounding_auc is not None]
    if first:
        lines += ["The first step's proposals across all held-out episodes, failed ones included (what the "
                  "planner's probes compare groundings by; the classifier learns from successful episodes only): "
                  + ", ".join(f"`{r.variable}` AUC {_fmt(r.grounding_auc)}" for r in first) + ".", ""]
    lines += [f"![learning curves]({png})", ""]
    return "\n".join(lines)


def write_report(markdown_path: str, png_path: str, name: str, reports: Sequence[ParamReport],
                 manifest: Dict[str, object], info: Dict[str, object]) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    curve = success_curve(manifest.get("episodes", []))
    axes[0].plot(np.arange(len(curve)), curve, color="tab:green")
    axes[0].set(title="self-play success (last 10 episodes)", xlabel="episode", ylim=(-0.02, 1.02))
    for r in reports:
        if r.train_loss:
            # Epochs counted from 1, as the table's "kept epoch" counts them.
            line, = axes[1].plot(np.arange(1, len(r.train_loss) + 1), r.train_loss, label=f"{r.variable} train")
            if r.validation_loss:
                axes[1].plot(np.arange(1, len(r.validation_loss) + 1), r.validation_loss, linestyle="--",
                             color=line.get_color(), label=f"{r.variable} val.")
    axes[1].set(title="classifier loss (BCE, class-balanced)", xlabel="epoch")
    axes[1].xaxis.set_major_locator(MaxNLocator(integer=True))
    axes[1].legend(fontsize=7)
    trained = [r for r in reports if not r.skipped]
    axes[2].bar([r.variable for r in trained], [r.auc if r.auc is not None else 0.0 for r in trained],
                color="tab:blue")
    axes[2].axhline(0.5, color="grey", linewidth=0.8, linestyle=":")
    axes[2].set(title="validation ROC AUC per parameter", ylim=(0, 1))
    fig.suptitle(f"mechanism {name}")
    fig.tight_layout()
    with atomic_file(png_path, binary=True, suffix=".png") as handle:
        fig.savefig(handle, format="png", dpi=90)
    plt.close(fig)
    write_text(markdown_path, report_markdown(name, reports, manifest, info, os.path.basename(png_path)))
