#!/usr/bin/env bash
# The mechanisms beyond the paper (gap-push, ramp-slide) and their composition with the
# paper's Hook (hook-ramp), measured once on held-out (test) instances, at one commit, after
# tuning on dev only (docs/evaluation.md). Run from a checkout of that commit with both
# checkpoints trained; every step resumes where an interrupted run stopped. OUT defaults to
# results/beyond-paper.
set -euo pipefail
OUT=${OUT:-results/beyond-paper}
PY=${PY:-python}
W=${WORKERS:-2}
run() { echo "+ $*" >&2; "$@"; }
mkdir -p $OUT/samplers
# The row: 10 held-out instances, 120 s, every solved plan replayed in a fresh world.
run $PY -m pdsketch_mech.bench mechanisms --split test --tasks gap-push,ramp-slide --methods macro+sampler,macro,basis \
    --timeout 120 --workers $W --out $OUT/table --quiet --resume
# Learned against generic samplers, median values simulated.
for name in gap-push ramp-slide; do
  [ -s $OUT/samplers/$name.json ] || run $PY -m pdsketch_mech.bench samplers $name --split test --workers $W \
      --json $OUT/samplers/$name.json --markdown $OUT/samplers/$name.md
done
# The composition with the paper's Hook, every mechanism loaded: 5 held-out instances, 600 s.
run $PY -m pdsketch_mech.bench compose --split test --tasks hook-ramp --methods macro+sampler --trials 5 \
    --timeout 600 --workers $W --out $OUT/compose --quiet --resume
