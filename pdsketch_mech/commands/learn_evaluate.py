"""`learn evaluate NAME`: a checkpoint's classifiers scored on self-play data (evaluate.py).

Prints the table on stdout and a one-line summary on stderr; exit 2 with one `error:` line
when the data, fragment or checkpoint cannot be used, 1 when no episode has a used and an
unused proposal of a classified parameter to rank.
"""
from __future__ import annotations

import os
import sys

from ..util.files import write_json
from .common import EXIT_OK, EXIT_UNSOLVED, fail, output_error


def evaluate_command(args) -> int:
    from ..learning.evaluate import as_json, data_config, held_out_episodes, markdown, score_episodes, summarise
    from ..learning.sampler_data import read_episodes
    from ..learning.selfplay_store import StoreError, check_definition
    from ..samplers.learned.checkpoint import CheckpointError, context_count, load, mechanism_hash
    from ..samplers.learned.ranked import checkpoint_path
    from .learn_train import fragment_mechanism, shown

    found = fragment_mechanism(args.name, args.fragment)
    if isinstance(found, int):
        return found
    fragment, mechanism = found
    data = args.data or os.path.join("out", "selfplay-dev", args.name)
    if not os.path.isdir(data):
        hint = "" if args.data else f" (make it with `python -m pdsketch_mech.learn selfplay {args.name} --split dev`)"
        return fail(f"{data}: no such folder{hint}")
    if args.json:
        error = output_error(args.json, "--json", (fragment,), (".json",))
        if error is not None:
            return fail(error.message)
    if args.checkpoint is None and not mechanism.sampler:
        return fail(f"{fragment}: mechanism {args.name} names no learned sampler; give --checkpoint")
    checkpoint = args.checkpoint or checkpoint_path(mechanism)
    if not os.path.isfile(checkpoint):
        return fail(f"{checkpoint}: no such file")
    try:
        model, meta = load(checkpoint, mechanism, os.path.abspath(fragment))
        episodes = read_episodes(data)
        held_out = held_out_episodes(data, episodes)
        config = data_config(data)
        # Episodes played with another definition of the mechanism rank other parameters.
        check_definition(data, config, mechanism_hash(mechanism), shown(fragment))
        split = config["split"]
    except (CheckpointError, StoreError) as exc:
        return fail(str(exc))
    # Classifiers trained with context objects (samplers/learned/context.py) read as many.
    theirs, ours = context_count(meta), int(config["context"])
    if theirs != ours:
        return fail(f"{data}: self-play recorded {ours} context object(s) per episode, but {shown(checkpoint)} "
                    f"was trained with {theirs}; play the data with --context {theirs}")
    if split == "train":
        print(f"warning: {data} holds train-split self-play: the classifiers may have been trained on these "
              "episodes, so the figures overstate what they do on new ones", file=sys.stderr)
    scored = score_episodes(model, episodes, held_out)
    rows = summarise(model, scored)
    sys.stdout.write(markdown(rows))
    ranked = sum(len(v) for v in scored.values())
    successes = sum(bool(ep["episode_success"][0]) for ep in episodes)
    print(f"evaluate {args.name}: {shown(checkpoint)} on {len(episodes)} episodes of {shown(data)} "
          f"({successes} successful, {sum(held_out.values())} with held-out categories); "
          f"{ranked} parameter rankings scored", file=sys.stderr)
    if args.json:
        write_json(args.json, as_json(rows, scored, {"mechanism": args.name, "checkpoint": shown(checkpoint),
                                                     "data": shown(data), "episodes": len(episodes)}))
    return EXIT_OK if ranked else EXIT_UNSOLVED
