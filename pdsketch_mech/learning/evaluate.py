"""How well a checkpoint's classifiers rank proposals of self-play episodes they never saw.

`learn selfplay NAME --split dev` plays the task's dev split (held-out objects and
categories included) with the generic samplers; `learn evaluate NAME` then scores, for every
successful episode and every parameter with a classifier, each proposal the generic sampler
drew as planning would (the calibrated log P(verifies and is used)) and compares the ranking
with the proposal(s) the successful plan used:

    AUC        the chance that a used proposal outranks an unused one drawn in the same
               context (0.5: no better than the generic sampler's random order)
    position   how many proposals a best-first walk verifies up to the first used one
    random     the same for a random order: (n + 1) / (k + 1), k used among n proposals
    gain       random / position per episode (above 1: the classifier saves verifications)

Figures are medians over episodes, seen and held-out categories apart. Unlike a planner
comparison (bench samplers), nothing here depends on time, load or the order in which a
search happens to backtrack: two checkpoints are compared on the very same proposals. The
labels undercount good proposals (self-play stops at its first success; another proposal
might have worked too), so the figures are lower bounds on what ranking is worth.
"""
from __future__ import annotations

import os
import statistics
from dataclasses import asdict, dataclass
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..envs.generate import sample
from ..envs.task_names import resolve_task
from .sampler_data import context_groups, param_data
from .sampler_training import roc_auc, to_batch
from .selfplay_store import StoreError, read_manifest

GROUPS = ("seen categories", "held-out categories", "all")
CHUNK = 4096  # rows scored per forward pass


@dataclass
class ContextScore:
    """How one context's proposals for a parameter were ranked."""

    episode: int
    held_out: bool
    proposals: int
    used: int
    auc: Optional[float]
    position: int          # 1-based rank of the best-ranked used proposal
    random: float          # a random order's expected position of the first used proposal

    @property
    def gain(self) -> float:
        return self.random / self.position


@dataclass
class ParamEvaluation:
    variable: str
    kind: str
    group: str
    contexts: int          # contexts ranked (one or more per episode)
    median_auc: Optional[float]
    median_position: Optional[float]
    median_random: Optional[float]
    median_gain: Optional[float]


def data_config(folder: str) -> Dict[str, object]:
    """The self-play configuration a data folder's manifest records."""
    manifest = read_manifest(folder)
    if manifest is None:
        raise StoreError(f"{os.path.join(folder, 'manifest.json')}: no such file (not a self-play folder)")
    return manifest["config"]


def held_out_episodes(folder: str, episodes: Sequence[Dict[str, np.ndarray]]) -> Dict[int, bool]:
    """Episode id -> whether its instance shows a category the task's train split never does."""
    config = data_config(folder)
    task, split = resolve_task(str(config["task"])), str(config["split"])
    return {int(ep["episode_id"][0]): sample(task, split, int(ep["episode_instance_seed"][0])).held_out
            for ep in episodes}


def score_episodes(model, episodes: Sequence[Dict[str, np.ndarray]],
                   held_out: Dict[int, bool]) -> Dict[str, List[ContextScore]]:
    """Per parameter with a classifier: one ContextScore per context (`context_groups`) of a
    successful episode in which the parameter had both a used and an unused proposal."""
    import torch
    out: Dict[str, List[ContextScore]] = {}
    for variable, spec in model.specs.items():
        data = param_data(episodes, spec, subsample=False)
        if not len(data):
            continue
        clouds = torch.from_numpy(data.clouds())
        classifier = model.classifier(variable)
        with torch.no_grad():
            scores = np.concatenate([classifier.log_score(to_batch(data, np.arange(i, min(i + CHUNK, len(data))),
                                                                   clouds)).numpy()
                                     for i in range(0, len(data), CHUNK)])
        rows: List[ContextScore] = []
        for mine in _contexts(data):
            labels = data.label[mine]
            used = int(labels.sum())
            if not used or used == len(mine):
                continue
            episode = int(data.episode[mine[0]])
            top_used = scores[mine][labels > 0.5].max()
            rows.append(ContextScore(episode, held_out[episode], len(mine), used, roc_auc(scores[mine], labels),
                                     1 + int((scores[mine] > top_used).sum()), (len(mine) + 1) / (used + 1)))
        out[variable] = rows
    return out


def _contexts(data) -> List[np.ndarray]:
    """The rows of the successful episodes, one array per (episode, context), in drawn order."""
    rows = np.flatnonzero(data.success > 0.5)
    keys = np.c_[data.episode[rows], context_groups(data)[rows]]
    _, key = np.unique(keys, axis=0, return_inverse=True)
    order = np.argsort(key.reshape(-1), kind="stable")
    cuts = np.flatnonzero(np.diff(key.reshape(-1)[order])) + 1
    return [rows[part] for part in np.split(order, cuts)] if len(rows) else []


def _median(values: List[float]) -> Optional[float]:
    return float(statistics.median(values)) if values else None


def summarise(model, scored: Dict[str, List[ContextScore]]) -> List[ParamEvaluation]:
    """Medians per parameter and group (seen categories, held-out categories, all)."""
    out = []
    for variable, rows in scored.items():
        for group in GROUPS:
            mine = [r for r in rows if group == "all" or r.held_out == (group == "held-out categories")]
            out.append(ParamEvaluation(variable, model.specs[variable].kind, group, len(mine),
                                       _median([r.auc for r in mine if r.auc is not None]),
                                       _median([r.position for r in mine]), _median([r.random for r in mine]),
                                       _median([r.gain for r in mine])))
    return out


def markdown(rows: List[ParamEvaluation]) -> str:
    """The evaluation as a markdown table."""
    fmt = lambda v, d=2: "-" if v is None else f"{v:.{d}f}"  # noqa: E731
    lines = ["| parameter | kind | contexts ranked | median AUC | median position (learned) | median position (random) "
             "| median gain |", "| :--- | :--- | :--- | ---: | ---: | ---: | ---: |"]
    lines += [f"| {r.variable} | {r.kind} | {r.group}: {r.contexts} | {fmt(r.median_auc)} | "
              f"{fmt(r.median_position, 1)} | {fmt(r.median_random, 1)} | {fmt(r.median_gain)} |" for r in rows
              if r.contexts or r.group == "all"]
    return "\n".join(lines) + "\n"


def as_json(rows: List[ParamEvaluation], scored: Dict[str, List[ContextScore]], info: Dict[str, object]) -> dict:
    return {**info, "summary": [asdict(r) for r in rows],
            "contexts": {v: [{**asdict(r), "gain": r.gain} for r in rs] for v, rs in scored.items()}}
