#!/usr/bin/env bash
# The one run of Tables 1 and 2 and the learned-vs-generic figures on the frozen test split
# (docs/evaluation.md), at one commit. Run from a checkout of that commit; every step
# resumes where an interrupted run stopped. OUT defaults to results/test-split.
set -euo pipefail
OUT=${OUT:-results/test-split}
PY=${PY:-python}
W=${WORKERS:-2}
run() { echo "+ $*" >&2; "$@"; }
mkdir -p $OUT/samplers
# Table 1: Macro+Sampler and every mechanism loaded, then Macro (generic samplers), 600 s as the paper.
run $PY -m pdsketch_mech.bench mechanisms --split test --methods macro+sampler,all-mechanisms --timeout 600 --workers $W --out $OUT/table1 --quiet --resume
# Table 2: Macro+Sampler, 600 s.
run $PY -m pdsketch_mech.bench compose --split test --methods macro+sampler --timeout 600 --workers $W --out $OUT/table2 --quiet --resume
# Learned against generic samplers, per mechanism: 10 test instances, 120 s.
for name in edge hook-use lever poking com slope-blocker; do
  [ -s $OUT/samplers/$name.json ] || run $PY -m pdsketch_mech.bench samplers $name --split test --workers $W \
      --json $OUT/samplers/$name.json --markdown $OUT/samplers/$name.md
done
run $PY -m pdsketch_mech.bench mechanisms --split test --methods macro --timeout 600 --workers $W --out $OUT/table1 --quiet --resume
run $PY -m pdsketch_mech.bench compose --split test --methods macro --timeout 600 --workers $W --out $OUT/table2 --quiet --resume
# Basis operators alone: a shorter limit, 120 s.
run $PY -m pdsketch_mech.bench mechanisms --split test --methods basis --timeout 120 --workers $W --out $OUT/table1-basis --quiet --resume
run $PY -m pdsketch_mech.bench compose --split test --methods basis --timeout 120 --workers $W --out $OUT/table2-basis --quiet --resume
