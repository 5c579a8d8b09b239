"""Training the classifiers of a mechanism's parameters on self-play data.

Each classifier has two logits (samplers/learned/model.py): "verifies" is trained on every
proposal with the label whether it verified; "used" on the values (verified proposals) of
the successful episodes, with the label whether the plan used them. Only successful
episodes: at planning time the context is given and the classifier's one job is to rank
values within it; with failed episodes' values as negatives it learns to tell contexts that
succeed from those that fail (a distractor grounded as the tool), which scores well on
held-out rows and ranks nothing (measured on hook-use: validation AUC 0.90, and the Hook
test instances no better than the generic order). Binary cross-entropy, each class-balanced
(positives weighted by negatives / positives: a successful episode uses one value per
parameter among dozens drawn), the log of each weight kept as the head's prior shift so that
planning ranks by calibrated probabilities; Adam, minibatches.
Episodes, not rows, are held out for validation (rows of one episode share their context).
With a few dozen positives a classifier soon fits its training rows and gets worse on
others (measured on hook-use: validation loss lowest around epoch 5 of 60, then rising
tenfold), so the weights of the epoch with the lowest validation loss are kept, and training
stops `patience` epochs after it (early stopping; the same rows then give the reported
figures, which are therefore a little optimistic). Reported per parameter: rows, positives,
the kept epoch, validation ROC AUC of the ranking score and of verification, and balanced
accuracy.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Sequence

import numpy as np
import torch
from torch import nn

from ..samplers.learned.model import Batch, MechanismClassifiers
from ..samplers.learned.specs import EncoderConfig
from .sampler_data import ParamData, param_data, parent_specs, split_episodes


@dataclass(frozen=True)
class TrainConfig:
    epochs: int = 30
    batch: int = 128
    lr: float = 1e-3
    weight_decay: float = 1e-3
    validation: float = 0.2      # share of episodes held out
    patience: int = 8            # stop after this many epochs without a lower validation loss
    seed: int = 0
    encoder: EncoderConfig = EncoderConfig()


@dataclass
class ParamReport:
    variable: str
    kind: str
    rows: int
    positives: int
    validation_rows: int = 0
    validation_positives: int = 0
    auc: Optional[float] = None              # ranking held-out proposals of successful episodes by log_score
                                             # against "used"; None: one class
    verify_auc: Optional[float] = None       # the "verifies" logit against verification's outcome
    grounding_auc: Optional[float] = None    # first-step proposals of every episode, failed ones too
    rejected: int = 0                        # rows that are proposals which failed verification
    balanced_accuracy: Optional[float] = None
    best_epoch: Optional[int] = None         # the epoch whose weights were kept (1-based)
    train_loss: List[float] = field(default_factory=list)
    validation_loss: List[float] = field(default_factory=list)
    skipped: str = ""                        # why no classifier was trained


def roc_auc(scores: np.ndarray, labels: np.ndarray) -> Optional[float]:
    """Area under the ROC curve (Mann-Whitney U with tied ranks averaged)."""
    pos, neg = labels > 0.5, labels <= 0.5
    if not pos.any() or not neg.any():
        return None
    order = np.argsort(scores, kind="stable")
    ranks = np.empty(len(scores))
    sorted_scores = scores[order]
    i = 0
    while i < len(scores):  # average ranks over ties
        j = i
        while j + 1 < len(scores) and sorted_scores[j + 1] == sorted_scores[i]:
            j += 1
        ranks[order[i:j + 1]] = (i + j) / 2.0 + 1
        i = j + 1
    n_pos, n_neg = int(pos.sum()), int(neg.sum())
    return float((ranks[pos].sum() - n_pos * (n_pos + 1) / 2) / (n_pos * n_neg))


def balanced_accuracy(scores: np.ndarray, labels: np.ndarray, threshold: float = 0.5) -> Optional[float]:
    pos, neg = labels > 0.5, labels <= 0.5
    if not pos.any() or not neg.any():
        return None
    return float(((scores[pos] > threshold).mean() + (scores[neg] <= threshold).mean()) / 2)


def to_batch(data: ParamData, rows: np.ndarray, clouds: torch.Tensor) -> Batch:
    t = torch.from_numpy
    return Batch(t(data.value[rows]), [t(p[rows]) for p in data.parents], t(data.present[rows]), clouds,
                 t(data.cloud_index[rows]), t(data.sizes[rows]), t(data.poses[rows]))


def train_mechanism(episodes: Sequence[Dict[str, np.ndarray]], config: TrainConfig,
                    progress: Optional[Callable[[str, int, float, float], None]] = None
                    ) -> tuple[MechanismClassifiers, List[ParamReport]]:
    """Classifiers for every rankable parameter with positives in the data; reports for all."""
    torch.manual_seed(config.seed)
    specs = parent_specs(episodes)
    datasets = {var: param_data(episodes, spec, config.seed) for var, spec in specs.items()}
    trainable = [spec for var, spec in specs.items() if datasets[var].label.sum() > 0]
    model = MechanismClassifiers(trainable, config.encoder)
    reports: List[ParamReport] = []
    for var, spec in specs.items():
        data = datasets[var]
        report = ParamReport(var, spec.kind, len(data), int(data.label.sum()),
                             rejected=int((data.verified < 0.5).sum()))
        reports.append(report)
        if spec not in trainable:
            report.skipped = "no value of it was ever in a successful plan"
            continue
        _train_one(model.classifier(var), data, config, report, progress)
    model.eval()
    return model, reports


def balance(labels: np.ndarray, weights: np.ndarray) -> float:
    """pos_weight that gives both classes the same total weight (1 if a class is missing)."""
    pos, neg = float(weights[labels > 0.5].sum()), float(weights[labels <= 0.5].sum())
    return neg / pos if pos > 0 and neg > 0 else 1.0


class TwoHeadLoss:
    """Weighted BCE of the "used" logit on values plus the "verifies" logit on all rows."""

    def __init__(self, data: ParamData, rows: np.ndarray):
        values = rows[(data.verified[rows] > 0.5) & (data.success[rows] > 0.5)]
        self.used_weight = balance(data.label[values], data.weight[values])
        self.verify_weight = balance(data.verified[rows], data.weight[rows])
        self.used = torch.from_numpy(data.label)
        self.verified = torch.from_numpy(data.verified)
        self.scored = torch.from_numpy(data.verified * data.success)  # rows the "used" logit learns from
        self.weight = torch.from_numpy(data.weight)

    def shift(self) -> torch.Tensor:
        return torch.log(torch.tensor([self.used_weight, self.verify_weight], dtype=torch.float32))

    def __call__(self, logits: torch.Tensor, rows: np.ndarray) -> torch.Tensor:
        bce = nn.functional.binary_cross_entropy_with_logits
        used, verified, weight = self.used[rows], self.verified[rows], self.weight[rows]
        w_used = self.scored[rows] * weight * torch.where(used > 0.5, self.used_weight, 1.0)
        w_verify = weight * torch.where(verified > 0.5, self.verify_weight, 1.0)
        loss_used = (bce(logits[:, 0], used, reduction="none") * w_used).sum() / w_used.sum().clamp_min(1e-9)
        loss_verify = (bce(logits[:, 1], verified, reduction="none") * w_verify).sum() / w_verify.sum()
        return loss_used + loss_verify


def _train_one(classifier: nn.Module, data: ParamData, config: TrainConfig, report: ParamReport,
               progress: Optional[Callable[[str, int, float, float], None]]) -> None:
    train_eps, held_eps = split_episodes(data.episode, config.validation, config.seed)
    train_rows = np.flatnonzero(np.isin(data.episode, list(train_eps)))
    held_rows = np.flatnonzero(np.isin(data.episode, list(held_eps)))
    if not data.label[train_rows].any():  # every positive fell in validation: train on all
        train_rows, held_rows = np.arange(len(data)), np.zeros(0, dtype=np.int64)
    clouds = torch.from_numpy(data.clouds())
    classifier.fit_statistics(to_batch(data, train_rows, clouds))
    loss_fn = TwoHeadLoss(data, train_rows)
    classifier.prior_shift.copy_(loss_fn.shift())
    optimiser = torch.optim.Adam(classifier.parameters(), lr=config.lr, weight_decay=config.weight_decay)
    rng = np.random.default_rng(config.seed)
    best = (float("inf"), None)
    for epoch in range(config.epochs):
        classifier.train()
        losses = []
        order = rng.permutation(train_rows)
        for start in range(0, len(order), config.batch):
            rows = order[start:start + config.batch]
            optimiser.zero_grad()
            loss = loss_fn(classifier(to_batch(data, rows, clouds)), rows)
            loss.backward()
            optimiser.step()
            losses.append(loss.item() * len(rows))
        report.train_loss.append(sum(losses) / len(train_rows))
        held_loss = float("nan")
        if len(held_rows):
            classifier.eval()
            with torch.no_grad():
                held_loss = float(loss_fn(classifier(to_batch(data, held_rows, clouds)), held_rows))
            report.validation_loss.append(held_loss)
            if held_loss < best[0]:
                best = (held_loss, {k: v.detach().clone() for k, v in classifier.state_dict().items()})
                report.best_epoch = epoch + 1
        if progress is not None:
            progress(report.variable, epoch, report.train_loss[-1], held_loss)
        if report.best_epoch is not None and epoch + 1 - report.best_epoch >= config.patience:
            break
    if best[1] is not None:
        classifier.load_state_dict(best[1])
    classifier.eval()
    report.validation_rows, report.validation_positives = len(held_rows), int(data.label[held_rows].sum())
    if len(held_rows):
        with torch.no_grad():
            batch = to_batch(data, held_rows, clouds)
            score = classifier.log_score(batch).numpy()
            logits = classifier(batch).numpy()
        within = data.success[held_rows] > 0.5  # ranking within contexts that have a positive
        report.auc = roc_auc(score[within], data.label[held_rows][within])
        # predicted "used": both balanced heads above even odds
        report.balanced_accuracy = balanced_accuracy(logits.min(axis=1), data.label[held_rows], threshold=0.0)
        report.verify_auc = roc_auc(logits[:, 1], data.verified[held_rows])
        if data.first_step.any():
            # Across episodes, failed ones included: what the planner's probes compare
            # groundings by (planner/probes.py), which the "used" logit never learns directly.
            first = data.first_step[held_rows] > 0.5
            report.grounding_auc = roc_auc(score[first], data.label[held_rows][first])
