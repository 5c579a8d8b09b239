"""`learn train NAME`: self-play, then training, then the checkpoint, the report and the
fragment's `:sampler` line.

    domains/mechanisms/NAME.samplers.safetensors   weights (safetensors: no code on load)
    domains/mechanisms/NAME.samplers.json          metadata: mechanism hash, encoder, data, seed, command
    domains/mechanisms/NAME.samplers.md / .png     the learning report
    domains/mechanisms/NAME.pddl                   gains `:sampler "NAME.samplers.safetensors"`

Self-play data stay in the data folder (default out/selfplay/NAME): a rerun with more
episodes only plays the missing ones, and training reads episodes 0..N-1 (--episodes N),
also when an earlier run left more on disk.
"""
from __future__ import annotations

import os
import sys
import time
from typing import TYPE_CHECKING, Dict, Optional, Sequence, Tuple, Union

from ..lang.edit import set_mechanism_sampler
from ..lang.errors import PddlError
from ..lang.nodes import Domain
from ..lang.parser import parse_file
from ..learning.sampler_data import parent_specs, read_episodes
from ..learning.sampler_report import write_report
from ..learning.sampler_training import TrainConfig, train_mechanism
from ..learning.selfplay_store import StoreError, first_episodes
from ..samplers.learned.checkpoint import SUFFIX, metadata_path, save
from ..util.files import write_text
from ..util.progress import progress_bar
from .common import EXIT_BAD_INPUT, fail, print_error

if TYPE_CHECKING:
    from ..lang.nodes import Mechanism


def shown(path: str) -> str:
    """A path as the user would type it: relative inside the working folder, else absolute."""
    full = os.path.abspath(path)
    return os.path.relpath(full) if full.startswith(os.getcwd() + os.sep) else full


def fragment_mechanism(name: str, fragment: Optional[str]) -> Union[Tuple[str, "Mechanism"], int]:
    """(the fragment: given, or domains/mechanisms/NAME.pddl; its mechanism NAME), or the exit
    status after one error line when the file or the mechanism is missing or does not parse."""
    from ..learning.selfplay import _domain, default_fragment, find_mechanism
    path = fragment or default_fragment(name)
    if not os.path.isfile(path):
        return fail(f"{path}: no such file" + ("" if fragment else f" (is {name} a mechanism?)"))
    try:
        return path, find_mechanism(_domain(os.path.abspath(path)), name)
    except PddlError as exc:
        print_error(exc)
        return EXIT_BAD_INPUT
    except ValueError as exc:
        return fail(str(exc))


def checkpoint_for(fragment: str, name: str) -> str:
    return os.path.join(os.path.dirname(os.path.abspath(fragment)), name + SUFFIX)


def point_fragment_at(fragment: str, name: str, checkpoint: str) -> bool:
    """Give the fragment's mechanism `:sampler "<checkpoint's file name>"`, the rest of the
    file as it was (comments included). Returns whether the file changed."""
    with open(fragment, encoding="utf-8") as handle:
        text = handle.read()
    domain = parse_file(fragment)
    assert isinstance(domain, Domain)
    wanted = os.path.relpath(os.path.abspath(checkpoint), os.path.dirname(os.path.abspath(fragment)))
    mechanism = next(m for m in domain.mechanisms if m.name == name)
    if mechanism.sampler == wanted:
        return False
    write_text(fragment, set_mechanism_sampler(text, mechanism, wanted.replace(os.sep, "/")))
    return True


def check_parameters(data: str, fragment: str, mechanism, variables: Sequence[str]) -> None:
    """StoreError if the episodes drew values for variables the mechanism does not have: they
    were played with another definition (a folder older than the manifest's mechanism_hash)."""
    foreign = [v for v in variables if v not in {p.name for p in mechanism.parameters}]
    if foreign:
        raise StoreError(f"{data} holds self-play episodes of another definition of mechanism {mechanism.name} "
                         f"than the one in {fragment} (they draw {', '.join(foreign)}, which it does not have); "
                         "use a new --out, or delete the folder to play them again")


class Unvalidated(Exception):
    """Classifiers that no held-out episode could validate (its proposals all of one class)."""

    def __init__(self, variables: Sequence[str], positives: int, episodes: int, all_used: bool = False):
        super().__init__(", ".join(variables))
        self.variables, self.positives, self.episodes = list(variables), positives, episodes
        self.all_used = all_used   # every held-out proposal was used: nothing was ever rejected


def train_and_save(name: str, mechanism, fragment: str, data: str, checkpoint: str, config: TrainConfig,
                   manifest: Dict[str, object], info: Dict[str, object], quiet: bool = False,
                   count: Optional[int] = None, unvalidated: bool = False) -> int:
    """Train on the episodes 0..count-1 in `data` (all if None), write checkpoint + metadata +
    report, point the fragment at the checkpoint. Returns how many classifiers were trained.
    Unvalidated (nothing written, the fragment untouched) if a trained classifier could not
    be validated on the held-out episodes, unless `unvalidated` (then a warning)."""
    episodes = read_episodes(data, count)
    if count is not None:
        manifest = first_episodes(manifest, count)  # the report describes the data trained on
    specs = parent_specs(episodes)
    check_parameters(data, fragment, mechanism, list(specs))
    started = time.perf_counter()
    total = len(specs) * config.epochs  # an upper bound: a parameter never used is skipped
    with progress_bar(total=total, unit="epoch", desc=f"train {name}", disable=quiet,
                      dynamic_ncols=True) as bar:
        def progress(variable: str, epoch: int, train_loss: float, held_loss: float) -> None:
            # refresh=False: a redraw here would show the new epoch beside the old count.
            bar.set_postfix_str(f"{variable} epoch {epoch + 1}/{config.epochs}: loss {train_loss:.3f}, "
                                f"validation {held_loss:.3f}", refresh=False)
            bar.update(1)
        model, reports = train_mechanism(episodes, config, progress)
        # Early stopping and skipped parameters end it before the bound; closing the bar draws
        # it once more (a refresh here would print its last line twice into a log).
        bar.total = bar.n
    info = {**info, "seconds_training": time.perf_counter() - started}
    untested = [r.variable for r in reports if not r.skipped and r.auc is None]
    if untested and not unvalidated:   # a classifier nothing held out could test is not handed to the planner
        held_out = [r for r in reports if r.variable in untested]
        raise Unvalidated(untested, sum(r.positives for r in reports), len(episodes),
                          all_used=all(r.validation_rows and r.validation_positives == r.validation_rows for r in held_out))
    if untested:
        print(f"warning: mechanism {name}: the classifiers of {', '.join(untested)} could not be validated "
              "(--unvalidated: written anyway)", file=sys.stderr)
    rows = sum(r.rows for r in reports)
    meta = {"fragment": os.path.relpath(fragment, os.path.dirname(checkpoint)), "seed": config.seed,
            "epochs": config.epochs, "episodes": len(episodes), "rows": rows,
            "selfplay": manifest.get("config", {}), "command": info["command"],
            "validation": {r.variable: {"auc": r.auc, "balanced_accuracy": r.balanced_accuracy,
                                        "verify_auc": r.verify_auc, "rows": r.validation_rows,
                                        "positives": r.validation_positives,
                                        **({"grounding_auc": r.grounding_auc} if r.grounding_auc is not None
                                           else {})}
                           for r in reports if not r.skipped},
            "skipped": {r.variable: r.skipped for r in reports if r.skipped}}
    save(checkpoint, model, mechanism, meta)
    base = checkpoint[:-len(".safetensors")]
    write_report(base + ".md", base + ".png", name, reports, manifest, info)
    changed = point_fragment_at(fragment, name, checkpoint)
    trained = [r for r in reports if not r.skipped]
    size = os.path.getsize(checkpoint) / 1e6
    print(f"train {name}: {len(trained)} classifiers ({', '.join(r.variable for r in trained) or 'none'}) "
          f"from {len(episodes)} episodes, {rows} proposals; wrote {shown(checkpoint)} ({size:.2f} MB), "
          f"{shown(metadata_path(checkpoint))}, {shown(base)}.md/.png"
          + (f"; {shown(fragment)} now names the checkpoint" if changed else ""), file=sys.stderr)
    for r in reports:
        figure = (f"validation AUC {r.auc:.3f}" if r.auc is not None
                  else "validation AUC - (the held-out episodes' rows hold one class only)")
        print(f"  {r.variable} ({r.kind}): {r.rows} proposals ({r.rejected} rejected), {r.positives} used; "
              + (f"not trained: {r.skipped}" if r.skipped else figure), file=sys.stderr)
    return len(trained)


def default_config(epochs: Optional[int], seed: int) -> TrainConfig:
    return TrainConfig(seed=seed) if epochs is None else TrainConfig(epochs=epochs, seed=seed)
