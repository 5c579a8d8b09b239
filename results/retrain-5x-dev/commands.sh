#!/usr/bin/env bash
# Retrain one mechanism's learned samplers on more self-play data and compare the new
# checkpoint with the one it replaces on dev (issue 67, item 2). Run from a checkout of the
# commit to start from; every step resumes where an interrupted run stopped:
#
#   NAME=poking EPISODES=2200 WORKERS=2 bash results/retrain-5x-dev/commands.sh
#
# The new checkpoint is written beside the fragment (domains/mechanisms/NAME.samplers.*);
# ship it only if the comparison printed last is no worse (as many solved, no more values).
set -euo pipefail
: "${NAME:?which mechanism}" "${EPISODES:?how many self-play episodes}"
PY=${PY:-python}
W=${WORKERS:-1}
DATA=${DATA:-out/selfplay/$NAME}
OUT=${OUT:-out/retrain/$NAME}
run() { echo "+ $*" >&2; "$@"; }
mkdir -p "$OUT"
[ -s "$OUT/old.json" ] || run $PY -m pdsketch_mech.bench samplers "$NAME" --instances 10 --split dev --json "$OUT/old.json"
run $PY -m pdsketch_mech.learn selfplay "$NAME" --episodes "$EPISODES" --seed 0 --budget 400 --workers "$W" --out "$DATA"
[ -s "$OUT/new.json" ] || {
  run $PY -m pdsketch_mech.learn train "$NAME" --episodes "$EPISODES" --seed 0 --budget 400 --out "$DATA" --force
  run $PY -m pdsketch_mech.bench samplers "$NAME" --instances 10 --split dev --json "$OUT/new.json"
}
$PY - "$OUT/old.json" "$OUT/new.json" <<'EOF'
import json, math, sys
def figures(path):
    trials = [t for t in json.load(open(path))["trials"] if t["method"] == "macro+sampler"]
    gm = lambda xs: math.exp(sum(math.log(max(x, 1)) for x in xs) / len(xs))
    return (sum(t["status"] == "solved" for t in trials), len(trials),
            gm([sum(t["simulated"].values()) for t in trials]), gm([sum(t["proposals"].values()) for t in trials]))
for label, path in zip(("old", "new"), sys.argv[1:]):
    print("%s: solved %d/%d, values simulated gm %.2f, proposals verified gm %.1f" % ((label,) + figures(path)))
EOF
