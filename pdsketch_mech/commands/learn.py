"""`python -m pdsketch_mech.learn extract|selfplay|train|evaluate`: demonstrations -> mechanisms -> learned samplers.

    extract DEMO [--name NAME] [--out FILE.pddl] [--render FILE.png] [--force]
        Segment the recording DEMO (NAME.npz, NAME.json or NAME) by contact modes, map the
        segments to basis operators, lift them to a mechanism and write it with the
        language's writer to FILE (default domains/mechanisms/NAME.pddl; NAME defaults to the
        recording's task). The timeline (frames, time, contact mode, supports, basis step) is
        printed on stdout. --render draws it under key frames. An existing FILE that differs
        from what would be written is kept (exit 2, saying what differs) unless --force.

    selfplay NAME [--episodes N] [--seed S] [--workers K] [--out DIR] [--budget UNITS]
                  [--time-limit S] [--fragment FILE] [--task TASK] [--split train|dev|test]
        Self-play (paper Alg. 2) of mechanism NAME (domains/mechanisms/NAME.pddl) on train
        instances of its task: every value the generic samplers draw, with its context,
        labelled 1 if the successful plan used it. Data go to DIR (default
        out/selfplay/NAME/; created with its parents if missing), one file per episode; a
        rerun resumes where a run stopped. A folder of other options, or of another
        definition of the mechanism, is refused.
        --split dev plays dev instances instead (default DIR out/selfplay-dev/NAME/):
        data for `evaluate`; `train` refuses a folder of them.
    train NAME [selfplay's options] [--epochs E] [--checkpoint FILE] [--force] [--compare N]
        Self-play as above (only the episodes not on disk yet), then train a classifier per
        grasp, contact and placement parameter on episodes 0..N-1, and write the
        checkpoint (default domains/mechanisms/NAME.samplers.safetensors), its .json
        metadata, a report (.md and .png beside it), and point the fragment's `:sampler` at
        the checkpoint. An existing checkpoint is replaced only with --force. --compare N then
        plans N dev instances with the generic and the learned samplers and adds the table and
        the per-sampler breakdown (the paper's Fig. 8) to the report.
    evaluate NAME [--data DIR] [--checkpoint FILE] [--fragment FILE] [--json FILE]
        Score every proposal of the successful episodes in DIR (default
        out/selfplay-dev/NAME/) with the checkpoint's classifiers and print, per parameter
        and for seen and held-out categories apart, how well the ranking finds the proposal
        the plan used (AUC; its position best-first against a random order's).

Exit status: 0 written (or already up to date), 1 the demonstration cannot be turned into a
mechanism (e.g. cut off before its goal holds), no self-play episode succeeded, or no
parameter had a value in a successful plan to train on; 2 bad input (one `error:` line).
"""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import time
from typing import Dict, List, Optional, Sequence

from ..learning.paths import NAME, repo_path
from ..util.progress import progress_bar
from ..lang.errors import PddlError
from .common import (
    ArgumentParser, EXIT_OK, EXIT_UNSOLVED, count, fail, output_error, output_folder, print_error, seconds, seed,
    whole,
)


def _parser() -> ArgumentParser:
    parser = ArgumentParser(prog="python -m pdsketch_mech.learn", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", parser_class=ArgumentParser)
    ext = commands.add_parser("extract", help="a recorded demonstration -> domains/mechanisms/NAME.pddl")
    ext.add_argument("demo", metavar="DEMO", help="a recording (NAME.npz, NAME.json or NAME)")
    ext.add_argument("--name", help="the mechanism's (and fragment's domain) name (default: the recording's task)")
    ext.add_argument("--out", metavar="FILE.pddl", help="where to write (default domains/mechanisms/NAME.pddl)")
    ext.add_argument("--render", metavar="FILE.png", help="draw the timeline under key frames")
    ext.add_argument("--force", action="store_true", help="replace an existing fragment that differs")
    play = commands.add_parser("selfplay", parents=[_selfplay_options()], add_help=False,
                               help="self-play data of mechanism NAME (labelled samples)")
    play.add_argument("-h", "--help", action="help", help="show this help message and exit")
    play.add_argument("--split", choices=("train", "dev", "test"), default="train",
                      help="the task's split the instances come from (default train; dev: data for "
                           "`evaluate`, in out/selfplay-dev/NAME by default, never trained on)")
    evaluate = commands.add_parser("evaluate", help="how well NAME's classifiers rank dev-split self-play proposals")
    evaluate.add_argument("name", metavar="NAME", help="the mechanism (domains/mechanisms/NAME.pddl)")
    evaluate.add_argument("--data", metavar="DIR", help="self-play data (default out/selfplay-dev/NAME, made by "
                          "`selfplay NAME --split dev`)")
    evaluate.add_argument("--fragment", metavar="FILE", help="the mechanism's fragment (default "
                          "domains/mechanisms/NAME.pddl)")
    evaluate.add_argument("--checkpoint", metavar="FILE", help="the classifiers (default: the one the fragment names)")
    evaluate.add_argument("--json", metavar="FILE", help="also write every episode's figures as JSON")
    train = commands.add_parser("train", parents=[_selfplay_options()], add_help=False,
                                help="self-play, then train mechanism NAME's samplers -> checkpoint + report")
    train.add_argument("-h", "--help", action="help", help="show this help message and exit")
    train.add_argument("--epochs", type=count, default=None, help="training epochs per parameter (default 30)")
    train.add_argument("--checkpoint", metavar="FILE", help="where to write the weights "
                       "(default domains/mechanisms/NAME.samplers.safetensors); the fragment's "
                       ":sampler is pointed at it")
    train.add_argument("--force", action="store_true", help="replace an existing checkpoint")
    train.add_argument("--unvalidated", action="store_true",
                       help="write the checkpoint even if a classifier could not be validated on held-out episodes "
                            "(a quick trial run), with a warning; by default nothing is written")
    train.add_argument("--compare", type=whole, default=0, metavar="N",
                       help="then plan N dev instances with the generic and the learned samplers (120 s each) and "
                            "add the table and the per-sampler breakdown (the paper's Fig. 8) to the report "
                            "(default 0: skip; `bench samplers NAME --report` does it later)")
    return parser


def _selfplay_options() -> ArgumentParser:
    """The options `selfplay` and `train` share."""
    play = ArgumentParser(add_help=False)
    play.add_argument("name", metavar="NAME", help="the mechanism (domains/mechanisms/NAME.pddl)")
    play.add_argument("--episodes", type=count, default=100, help="episodes 0..N-1 (default 100)")
    play.add_argument("--seed", type=seed, default=0, help="base seed: episode i uses seeds of (S, i) (default 0)")
    play.add_argument("--workers", type=count, default=1, help="processes running episodes (default 1)")
    play.add_argument("--out", metavar="DIR", help="data folder, created if missing (default out/selfplay/NAME)")
    play.add_argument("--budget", type=count, default=400, metavar="UNITS",
                      help="work units per episode: samples drawn and simulated (default 400)")
    play.add_argument("--time-limit", type=seconds, default=300.0, metavar="S",
                      help="seconds per episode, a safety net (default 300)")
    play.add_argument("--fragment", metavar="FILE", help="the mechanism's fragment (default domains/mechanisms/NAME.pddl)")
    play.add_argument("--task", help="the task distribution (default: NAME's, or its demonstration's); a problem "
                                     "file (.pddl) stands for its default distribution")
    play.add_argument("--grounding", choices=("goal", "any"), default="goal",
                      help="which groundings an episode draws from: goal (default): those whose certified facts "
                           "achieve part of the instance's goal, as the planner grounds it; any: every one whose "
                           "precondition holds (the paper's random grounding)")
    play.add_argument("--context", type=int, choices=range(0, 4), default=0, metavar="N",
                      help="also record the N bodies nearest the mechanism's movable objects (a tunnel around "
                           "the block), so its classifiers see them (0-3, default 0)")
    play.add_argument("--backend", choices=("local", "ray"), default="local",
                      help="local: K processes; ray: K Ray tasks at a time (a local instance, or RAY_ADDRESS's cluster)")
    return play


def _inputs(args, config, out: str) -> List[str]:
    """The options of a self-play or training command that name other inputs than the
    defaults (a fragment, a task, a data folder): re-running the command without them would
    read, or write, the repository's own."""
    from ..learning.selfplay import default_fragment
    words: List[str] = []
    if os.path.abspath(default_fragment(args.name)) != os.path.abspath(config.fragment):
        words += ["--fragment", repo_path(config.fragment)]
    if args.task is not None:   # a distribution file as the user would name it, or a task's name
        words += ["--task", repo_path(config.task) if os.path.isfile(config.task) else config.task]
    if args.out is not None:
        words += ["--out", repo_path(out)]
    return words


def extract_command(args) -> int:
    from .learn_extract import extract_command as run
    return run(args)


def selfplay_command(args) -> int:
    prepared = _prepare_selfplay(args)
    if isinstance(prepared, int):
        return prepared
    config, out, _ = prepared
    manifest = _selfplay(args, config, out)
    if manifest["totals"]["successes"]:
        return EXIT_OK
    print(f"selfplay {args.name}: none of the {manifest['totals']['episodes']} episodes in {out} succeeded, so no "
          f"proposal is labelled 1 for `train` to learn from ({_what_to_try(config, manifest.get('episodes', []))})",
          file=sys.stderr)
    return EXIT_UNSOLVED


def train_command(args) -> int:
    from ..learning.selfplay_store import StoreError, first_episodes
    from .learn_train import Unvalidated, checkpoint_for, default_config, train_and_save

    prepared = _prepare_selfplay(args)
    if isinstance(prepared, int):
        return prepared
    config, out, mechanism = prepared
    checkpoint = args.checkpoint or checkpoint_for(config.fragment, mechanism.name)
    if not checkpoint.endswith(".safetensors"):
        return fail(f"--checkpoint {checkpoint}: the weights file's name must end in .safetensors")
    error = output_error(checkpoint, "--checkpoint", (config.fragment,), (".safetensors",))
    if error is not None:
        return fail(error.message)
    if os.path.exists(checkpoint) and not args.force:
        return fail(f"{checkpoint} exists: --force replaces it (and its metadata and report)")
    started = time.perf_counter()
    manifest = _selfplay(args, config, out)
    selfplay_s = time.perf_counter() - started
    # Training reads episodes 0..--episodes-1 (all on disk now), not what an earlier run left
    # beyond them: the same command gives the same checkpoint.
    used = first_episodes(manifest, args.episodes)
    if not used["totals"]["successes"]:
        return _skipped(args, config, out, used)
    words = ["python -m pdsketch_mech.learn train", args.name] + _data_options(args, config, out)
    if args.epochs is not None:
        words += ["--epochs", str(args.epochs)]
    if args.checkpoint is not None:
        words += ["--checkpoint", repo_path(checkpoint)]
    if args.unvalidated:
        words += ["--unvalidated"]
    info = {"command": " ".join(words), "task": config.task, "seconds_selfplay": selfplay_s}
    try:
        trained = train_and_save(mechanism.name, mechanism, config.fragment, out, checkpoint,
                                 default_config(args.epochs, args.seed), manifest, info, count=args.episodes,
                                 unvalidated=args.unvalidated)
    except StoreError as exc:
        return fail(str(exc))
    except Unvalidated as exc:
        advice = ("every proposal the held-out episodes drew was used: the samplers' first values already "
                  "succeed, so there is nothing to learn and the mechanism plans as well without a checkpoint"
                  if exc.all_used else "play more --episodes, or narrow the task distribution so that more of "
                  "them succeed")
        print_error(PddlError(f"mechanism {mechanism.name}: the classifiers of {', '.join(exc.variables)} could not be "
                              f"validated (the held-out self-play episodes' proposals are all of one class; "
                              f"{exc.episodes} episodes used): no checkpoint written and the fragment unchanged; "
                              f"{advice}", mechanism.loc))
        return EXIT_UNSOLVED
    if trained and args.compare:
        _compare(mechanism.name, config, checkpoint, args.compare)
    return EXIT_OK if trained else EXIT_UNSOLVED


def _skipped(args, config, out: str, used: Dict[str, object]) -> int:
    """Say why nothing was trained: no episode succeeded, so no proposal is labelled 1."""
    print(f"train {args.name}: skipped: none of the {used['totals']['episodes']} self-play episodes in {out} "
          f"succeeded, so no proposal is labelled 1 to learn from ({_what_to_try(config, used['episodes'])})",
          file=sys.stderr)
    return EXIT_UNSOLVED


def _what_to_try(config, rows: Sequence[Dict[str, object]]) -> str:
    """What to try when none of the self-play episodes (manifest rows) succeeded: raise the
    limits they hit, or play more of them."""
    failed = [r for r in rows if not r["success"]]
    timed = sum(bool(r.get("timed_out")) for r in failed)
    spent = sum(not r.get("timed_out") and int(r.get("units", 0)) >= config.budget for r in failed)
    hit = [f"{n} {what}" for n, what in ((timed, f"hit --time-limit {config.time_limit:g} s"),
                                         (spent, f"used up --budget {config.budget}")) if n]
    if not hit:  # each search ended within its limits: the mechanism's steps found no values there
        return "none ran out of time or budget: the mechanism found no values in those instances; play more --episodes"
    return f"{' and '.join(hit)}: raise {'it' if len(hit) == 1 else 'them'}, or play more --episodes"


def _compare(name: str, config, checkpoint: str, instances: int) -> None:
    """Generic vs learned samplers on dev instances, into the learning report (Fig. 8): the
    `bench samplers` command, in its own process (benchmarks sit above the commands)."""
    print(f"compare {name}: {instances} dev instances, generic then learned samplers", file=sys.stderr)
    subprocess.run([sys.executable, "-m", "pdsketch_mech.bench", "samplers", name, "--fragment", config.fragment,
                    "--task", config.task, "--instances", str(instances), "--split", "dev", "--timeout", "120",
                    "--report"], check=False)


def _prepare_selfplay(args):
    """(config, data folder, mechanism) for `selfplay` and `train`, or an exit status."""
    from ..learning.selfplay import SelfPlayConfig, task_of
    from ..learning.selfplay_store import StoreError, open_folder

    if args.backend == "ray" and importlib.util.find_spec("ray") is None:
        return fail("--backend ray: ray is not installed (pip install -e '.[ray]')")
    if not NAME.match(args.name):
        return fail(f"{args.name}: a name is a lower-case letter, then letters, digits, '-' or '_'")
    from .learn_train import fragment_mechanism
    found = fragment_mechanism(args.name, args.fragment)
    if isinstance(found, int):
        return found
    fragment, mechanism = found
    from ..envs.task_file import TaskFileError, is_task_file
    from ..envs.task_names import resolve_task, task_names
    task = args.task or task_of(fragment, args.name)
    if task is None:
        return fail(f"{args.name}: no task distribution of that name or of its demonstration; give --task "
                    f"({', '.join(task_names())}, a distribution file NAME.dist.json, or the problem file "
                    "the demonstration was performed in: its default distribution)")
    try:
        resolve_task(task)
    except KeyError as exc:
        return fail(f"--task {exc.args[0]}")
    except TaskFileError as exc:
        print(exc, file=sys.stderr)
        return 2
    if task not in task_names() and (is_task_file(task) or task.endswith(".pddl")):
        task = os.path.abspath(task)   # episodes resolve it in their own processes, wherever they run
    split = getattr(args, "split", "train")  # `train` always plays the train split
    out = args.out or os.path.join("out", "selfplay" if split == "train" else f"selfplay-{split}", args.name)
    problem = output_folder(out, "--out")   # with its parents, as `demo record --out` makes its folder
    if problem is not None:
        return fail(problem)
    config = SelfPlayConfig(mechanism.name, os.path.abspath(fragment), task, args.seed, args.budget, args.time_limit,
                            split, args.grounding, args.context)
    try:
        open_folder(out, config.identity(), repo_path(config.fragment))
    except StoreError as exc:
        return fail(str(exc))
    except OSError as exc:
        return fail(f"--out {out}: cannot create: {exc.strerror}")
    return config, out, mechanism


def _data_options(args, config, out: str) -> List[str]:
    """The options that say which self-play data a command plays or reads (the folder's
    configuration, which a rerun must repeat, and the other inputs)."""
    from ..learning.selfplay import SelfPlayConfig
    return (["--episodes", str(args.episodes), "--seed", str(args.seed), "--budget", str(args.budget)]
            + (["--time-limit", f"{config.time_limit:g}"] if config.time_limit != SelfPlayConfig.time_limit else [])
            + (["--split", config.split] if config.split != "train" else [])
            + (["--grounding", config.grounding] if config.grounding != "goal" else [])
            + (["--context", str(config.context)] if config.context else []) + _inputs(args, config, out))


def _selfplay(args, config, out: str) -> Dict[str, object]:
    """Play the episodes of 0..--episodes-1 not on disk yet; returns the folder's manifest."""
    from ..learning.selfplay_run import pending, run_selfplay

    start = time.perf_counter()
    todo = len(pending(out, args.episodes))
    if todo < args.episodes:
        print(f"resuming: {args.episodes - todo} of {args.episodes} episodes on disk in {out}"
              + ("" if todo else ", none to play"), file=sys.stderr)
    counts = {"successes": 0, "samples": 0}
    command = " ".join(["python -m pdsketch_mech.learn selfplay", args.name] + _data_options(args, config, out))
    with progress_bar(total=todo, unit="episode", dynamic_ncols=True, desc=f"selfplay {args.name}",
                      disable=not todo) as bar:  # nothing to play: no empty bar
        def progress(row) -> None:
            counts["successes"] += row["success"]
            counts["samples"] += row["samples"]
            rate = counts["samples"] / max(1e-9, time.perf_counter() - start)
            # refresh=False: a redraw here would show this episode's success beside the old count.
            bar.set_postfix_str(f"{counts['successes']} succeeded, {rate:.1f} samples/s", refresh=False)
            bar.update(1)
        manifest = run_selfplay(config, out, args.episodes, args.workers, progress, command, args.backend)
    totals = manifest["totals"]
    size = sum(os.path.getsize(os.path.join(root, f)) for root, _, files in os.walk(out) for f in files)
    share = 100.0 * totals["successes"] / max(1, totals["episodes"])
    print(f"selfplay {args.name}: {totals['episodes']} episodes in {out} ({todo} run now, "
          f"{time.perf_counter() - start:.1f} s), {totals['successes']} succeeded ({share:.0f} %), "
          f"{totals['timed_out']} hit --time-limit {config.time_limit:g} s, "
          f"{totals['samples']} samples ({totals['positives']} labelled 1), {size / 1e6:.2f} MB", file=sys.stderr)
    return manifest


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = _parser().parse_args(argv)
    if args.command is None:
        return fail("give a command: extract, selfplay, train, evaluate")
    if args.command == "evaluate":
        from .learn_evaluate import evaluate_command
        return evaluate_command(args)
    return {"extract": extract_command, "selfplay": selfplay_command, "train": train_command}[args.command](args)
