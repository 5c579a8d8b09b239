"""Why no plan was found, in a line: the steps never feasible where their objects start (the
evidence's dead steps: a box out of reach), then the steps that failed most often and how,
from the refinements' failures per step (refine.py) and the proposals each step's samplers
verified (bindings.py). Statistics only: nothing here steers the search."""
from __future__ import annotations

from collections import Counter
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

NO_VALUES = "no feasible parameters"   # refine.py's reason for a visit that drew no value
SHOWN = 2                              # steps a hint names
KEPT = 4                               # steps the statistics keep, besides the dead ones


def failed_steps(step_failures: Mapping[Tuple[str, str], int],
                 verified: Mapping[Tuple[str, str, bool], Sequence[int]],
                 dead: Sequence[str] = ()) -> Dict[str, Dict[str, object]]:
    """Per step (operator and objects): the `dead` ones (in the order found), then those that
    failed most, most first. Each with how often it failed, why (the commonest reasons), and
    per sampler the proposals it verified for the step and how many of them were feasible
    (`verified`: by step, sampler and whether the step's objects lay where the scene began;
    a dead step counts only those, the others every proposal)."""
    by_step: Dict[str, Counter] = {}
    for (label, why), count in step_failures.items():
        by_step.setdefault(label, Counter())[why] += count
    # Ordered by the commonest single reason, then the total: "how" names one reason.
    failing = sorted((label for label in by_step if label not in dead),
                     key=lambda label: (-max(by_step[label].values()), -sum(by_step[label].values()), label))
    out: Dict[str, Dict[str, object]] = {}
    for label in [*dead, *failing[:KEPT]]:
        whys = by_step.get(label, Counter())
        proposals: Dict[str, Dict[str, int]] = {}
        for (step, sampler, at_start), tally in sorted(verified.items()):
            if step == label and (at_start or label not in dead):
                counts = proposals.setdefault(sampler, {"verified": 0, "feasible": 0})
                counts["verified"] += tally[0]
                counts["feasible"] += tally[1]
        out[label] = {"failures": sum(whys.values()), "why": dict(whys.most_common(3)), "proposals": proposals}
        if label in dead:
            out[label]["dead"] = True
    return out


def failure_hint(failed: Mapping[str, Mapping[str, object]], mechanisms: bool,
                 by_mechanism: Optional[Mapping[str, Mapping[str, int]]] = None,
                 set_aside: Sequence[str] = ()) -> Optional[str]:
    """The hint an unsolved run prints: first a mechanism that got in the way (its certified
    facts failed more often than any step failed otherwise, in skeletons it crowded: what to
    try instead), then the steps never feasible where their objects start, then the steps
    that failed most and how (SHOWN steps in all, and the commonest failure always), and,
    when the domain was planned without mechanisms, that one may help (those loaded but
    `set_aside` by --basis-only, or any); None when there is nothing to say."""
    parts: List[str] = []
    blocker = _mechanism_in_the_way(failed, by_mechanism or {})
    if blocker:
        parts.append(blocker)
    # A dead step's counts are those of its visits where its objects start: none is feasible there.
    dead = [f"{label}{_proposals(entry)}" for label, entry in failed.items() if entry.get("dead")][:SHOWN]
    most = [_how(label, entry) for label, entry in failed.items() if not entry.get("dead") and entry["why"]]
    if dead:
        parts.append("never feasible where its objects start: " + ", ".join(dead))
    # The commonest failure always: steps never feasible where the scene began may be beside
    # the point (a mechanism's step refused 200 times, where its objects had moved).
    shown = most[:max(1, SHOWN - len(dead))]
    if shown:
        parts.append("most failures: " + ", then ".join(shown))
    if not mechanisms:
        them = "it" if len(set_aside) == 1 else "them"
        parts.append(f"planned without {', '.join(set_aside)} (--basis-only): with {them}, it may solve" if set_aside
                     else "a mechanism (--mechanisms all) may help")
    return "; ".join(parts) or None


def _mechanism_in_the_way(failed: Mapping[str, Mapping[str, object]],
                          by_mechanism: Mapping[str, Mapping[str, int]]) -> Optional[str]:
    """`mechanism 'X' got in the way: its certified facts failed N times in K of M skeletons;
    try ...` for the mechanism whose broken promise is the run's commonest failure."""
    if not by_mechanism:
        return None
    name, row = max(by_mechanism.items(), key=lambda item: (item[1]["certified_failed"], item[0]))
    broken = row["certified_failed"]
    others = [entry["failures"] for label, entry in failed.items() if label.split()[0] != name]
    if not broken or broken < max(others, default=0):
        return None
    return (f"mechanism '{name}' got in the way: its certified facts failed {broken} times, in "
            f"{row['skeletons']} of {row['of']} skeletons; plan without it (leave it out of --mechanisms, "
            "or --basis-only) to see whether the basis operators solve this scene, and retrain it "
            "(learn train) on scenes like this one")


def _how(label: str, entry: Mapping[str, object]) -> str:
    """`place hook box (no feasible parameters, N times: K of M placement proposals feasible)`."""
    why, count = next(iter(entry["why"].items()))
    text = f"{label} ({why}, {count} time{'s' * (count != 1)}"
    return text + (_proposals(entry, inner=True) if why == NO_VALUES else "") + ")"


def _proposals(entry: Mapping[str, object], inner: bool = False) -> str:
    """What the step lacked: the sampler that let fewest of its proposals through, as
    ` (0 of M grasp proposals feasible)`, or ` (no grasp proposals)` when it proposed none
    (`: ...` inside other parentheses); '' if no sampler was asked."""
    proposals = entry["proposals"]
    if not proposals:
        return ""
    sampler, tally = min(proposals.items(),
                         key=lambda item: (item[1]["feasible"] / max(item[1]["verified"], 1) if item[1]["verified"]
                                           else -1.0, item[0]))
    text = (f"{tally['feasible']} of {tally['verified']} {sampler} proposals feasible" if tally["verified"]
            else f"no {sampler} proposals")
    return f": {text}" if inner else f" ({text})"
