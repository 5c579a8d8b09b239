"""`Planner`: load a domain and its mechanisms once, then plan, replay and check many
problems in the same process. Each `plan` returns the document `plan --json` writes."""
from __future__ import annotations

import json
import sys
import time
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from ..lang.errors import PddlError, PddlWarning
from ..lang.loader import LoadedDomain, load_domain, load_problem
from ..lang.nodes import Problem
from ..lang.source import read_text
from ..learning.paths import resolve_domain, resolve_mechanisms, resolve_problem
from ..planner.plan_document import check_plan, load_plan, plan_document, stale_model_note
from ..symbolic.ground_size import DEFAULT_MAX_GROUND, check_ground_size

PlanDocument = Dict[str, Any]


class Planner:
    """A domain (a path or a shipped name such as `"basis"`) with mechanisms (paths, shipped
    names, or `"all"`), loaded once. Bad files raise `PddlError` (its `str` is the one
    `FILE:LINE:COL: error: ...` line the commands print).

    `learned_samplers=False` is the paper's Macro ablation (generic samplers inside
    mechanisms); `basis_only=True` ignores the mechanisms."""

    def __init__(self, domain: str = "basis", mechanisms: Union[str, Sequence[str]] = (), *,
                 learned_samplers: bool = True, basis_only: bool = False,
                 max_ground: float = float(DEFAULT_MAX_GROUND)) -> None:
        self.use_learned = learned_samplers and not basis_only
        self.basis_only = basis_only
        self.max_ground = max_ground
        files = [resolve_domain(domain), *resolve_mechanisms(mechanisms)]
        self.domain: LoadedDomain = load_domain(files, samplers_required=self.use_learned)
        self.warnings: List[PddlWarning] = list(self.domain.warnings)
        self._learned: Optional[Mapping[str, object]] = None
        self._anchored: Optional[Mapping[str, object]] = None

    def load(self, problem: str) -> Tuple[LoadedDomain, Problem]:
        """Parse and check a problem file (a path or a shipped problem's name) against the domain."""
        loaded, parsed = load_problem(resolve_problem(problem), [self.domain], samplers_required=self.use_learned)
        check_ground_size(loaded.domain, parsed, loaded.types, self.max_ground)
        return loaded, parsed

    def check(self, problem: str) -> List[PddlWarning]:
        """Raise `PddlError` if `problem` is not valid for the domain; else its warnings."""
        loaded, _ = self.load(problem)
        return list(loaded.warnings)

    def plan(self, problem: str, *, timeout: float = 600.0, seed: int = 0, validate: bool = False,
             render: Optional[str] = None) -> PlanDocument:
        """Plan within `timeout` seconds of this call. A plan is only reported solved once it
        has reached the goal re-executed in a fresh world; `validate` replays it once more (as
        `plan --validate`) and adds `"replay"` to the document; `render` saves that replay as a GIF."""
        started = time.perf_counter()
        loaded, parsed = self.load(problem)
        if not loaded.domain.streams:
            return _plan_classical(loaded, parsed, timeout, seed, started)
        result, entries = plan_scene(loaded, parsed, started, started + timeout, seed,
                                     self.basis_only, self._learned_samplers(loaded),
                                     anchors=self._anchors(loaded))
        document = plan_document(result.status, result.reason or result.status, time.perf_counter() - started,
                                 seed, entries, result.stats, parsed.name)
        if result.status == "solved" and (validate or render):
            replayed = replay_entries(loaded, parsed, entries, render)
            document["replay"] = {"goal_reached": replayed.goal_reached, "message": replayed.message}
        return document

    def replay(self, problem: str, plan: Union[str, PlanDocument], *, render: Optional[str] = None
               ) -> Dict[str, Any]:
        """Re-execute a plan (a `plan --json` file or the document `plan` returned) in a fresh
        world: `{"goal_reached": bool, "message": str}`."""
        loaded, parsed = self.load(problem)
        steps = load_plan(plan, loaded, parsed) if isinstance(plan, str) else check_plan(plan, loaded, parsed)
        replayed = replay_entries(loaded, parsed, steps, render)
        message, note = replayed.message, None
        if not replayed.goal_reached:
            note = stale_model_note(json.loads(read_text(plan)) if isinstance(plan, str) else plan)
        return {"goal_reached": replayed.goal_reached, "message": f"{message} ({note})" if note else message}

    def _anchors(self, loaded: LoadedDomain) -> Mapping[str, object]:
        if self._anchored is None:   # read once, like the checkpoints
            self._anchored = mechanism_anchors(loaded, self.use_learned, not self.basis_only)
        return self._anchored

    def _learned_samplers(self, loaded: LoadedDomain) -> Mapping[str, object]:
        if self._learned is None:   # checkpoints are read once, for every problem after
            self._learned = learned_samplers(loaded, self.use_learned, not self.basis_only)
        return self._learned


def learned_samplers(loaded: LoadedDomain, use_learned: bool, use_mechanisms: bool) -> Dict[str, object]:
    """The mechanisms' learned samplers (scored in numpy: planning never imports torch), or
    none. A checkpoint that cannot be read raises `CheckpointError`, never falls back."""
    if not use_learned or not use_mechanisms or not any(m.sampler for m in loaded.domain.mechanisms):
        return {}
    _load_simulator_quietly()
    from ..samplers.learned.ranked import load_learned
    return load_learned(loaded.domain.mechanisms)


def mechanism_anchors(loaded: LoadedDomain, use_learned: bool, use_mechanisms: bool) -> Dict[str, object]:
    """What each mechanism's demonstration did (`NAME.anchors.json` beside its fragment), or
    none: the generic-sampler ablation (`--no-learned-samplers`, the paper's Macro) uses none.
    A malformed anchors file is a `PddlError` at its mechanism."""
    if not use_learned or not use_mechanisms:
        return {}
    from ..samplers.anchored import anchors_beside
    found = {}
    for mechanism in loaded.domain.mechanisms:
        try:
            anchors = anchors_beside(mechanism.loc.file if mechanism.loc is not None else "", mechanism.name)
        except (ValueError, OSError) as exc:
            raise PddlError(f"mechanism {mechanism.name}: its anchors cannot be read: {exc}", mechanism.loc) from None
        if anchors is not None:
            found[mechanism.name] = anchors
    return found


def _load_simulator_quietly() -> None:
    """PyBullet prints a banner on stdout when it loads; a command's import hook hides it,
    a library caller's output is kept clean here instead."""
    if "pybullet" not in sys.modules:
        from ..util.quiet_pybullet import silenced
        with silenced():
            import pybullet  # noqa: F401


def plan_scene(loaded: LoadedDomain, problem: Problem, started: float, deadline: float, seed: int,
               basis_only: bool, learned: Mapping[str, object],
               on_warning: Optional[Callable[[PddlWarning], None]] = None,
               anchors: Optional[Mapping[str, object]] = None):
    """The bilevel planner on `problem`'s scene until `deadline` (`time.perf_counter()` values,
    like `started`, when the caller's clock began): (PlanResult, the plan's JSON entries). The
    statistics get `startup_s` (until planning began: loading, world building), `planning_s`
    (the algorithm's own time, what a paper's planning time measures), `learned_samplers`,
    `scene_warnings`, the located warnings of the scene (objects that would fall), which
    `on_warning` is also told of before planning starts, and for an unsolved run `hint`:
    the steps that failed most and how (planner/failure_hint.py)."""
    _load_simulator_quietly()
    from ..planner.bilevel import bilevel_plan
    from ..planner.serialize import plan_entries
    from ..world.build import build_world

    if problem.scene is None:
        raise PddlError(f"problem '{problem.name}' has no :scene; domain '{loaded.domain.name}' has "
                        "streams, so the planner needs the physical scene", problem.loc)
    scene_warnings: List[PddlWarning] = []
    with build_world(problem, visual=False, warnings=scene_warnings) as world:   # a GIF is rendered from a fresh replay
        for warning in scene_warnings if on_warning is not None else ():
            on_warning(warning)
        began = time.perf_counter()
        result = bilevel_plan(loaded, problem, world, timeout=max(0.1, deadline - began), seed=seed,
                              use_mechanisms=not basis_only, learned=learned, anchors=anchors)
        result.stats["planning_s"] = round(time.perf_counter() - began, 3)
    result.stats["startup_s"] = round(began - started, 3)
    result.stats["learned_samplers"] = sorted(learned) if learned else "off"
    if result.status != "solved":
        from ..planner.failure_hint import failure_hint
        hint = failure_hint(result.stats.get("failed_steps", {}), not basis_only and bool(loaded.domain.mechanisms),
                            result.stats.get("mechanisms"),
                            set_aside=[m.name for m in loaded.domain.mechanisms] if basis_only else ())
        if hint:
            result.stats["hint"] = hint
    if scene_warnings:
        result.stats["scene_warnings"] = [str(w) for w in scene_warnings]
    return result, plan_entries(result.steps, result.values)


def replay_entries(loaded: LoadedDomain, problem: Problem, entries: Sequence[Dict[str, Any]],
                   render: Optional[str] = None, view=None):
    """Execute plan entries in a fresh world; with `render`, save the replay as a GIF, the
    camera framing the scene from `view` (a world.render.View; default: its default)."""
    _load_simulator_quietly()
    from ..operators.execution import FrameRecorder
    from ..planner.replay import replay
    from ..world.render import View, save_gif

    recorder = FrameRecorder(view=view or View()) if render else None
    result = replay(loaded, problem, entries, recorder=recorder)
    if render:
        save_gif(recorder.frames, render)
    return result


def _plan_classical(loaded: LoadedDomain, problem: Problem, timeout: float, seed: int, started: float
                    ) -> PlanDocument:
    from ..symbolic.solve import solve

    remaining = max(1e-3, timeout - (time.perf_counter() - started))
    result = solve(loaded.domain, problem, loaded.types, "gbfs", 2.0, remaining)
    status = "solved" if result.status == "solved" else "unsolved"
    return plan_document(status, result.status, time.perf_counter() - started, seed,
                         [{"name": name, "args": list(a), "params": {}} for name, a in result.plan],
                         {"skeletons": 1, "samples": {}, **result.stats}, problem.name)
