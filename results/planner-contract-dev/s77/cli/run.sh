#!/bin/bash
# Session 77's CLI check (from the checkout's root, venv active): each new problem planned as a
# user would, with basis operators only, every shipped mechanism, and the user's shelf pull.
# The runs were written to OUT and summarised in runs.jsonl (their JSON documents not kept).
HERE=results/planner-contract-dev/s77/cli
OUT=${OUT:-/tmp/s77-cli}
mkdir -p $OUT
for P in $HERE/*.pddl; do
  n=$(basename $P .pddl)
  for cfg in basis all shelf; do
    case $cfg in
      basis) args="--basis-only";;
      all) args="--mechanisms all";;
      shelf) args="--mechanisms problems/contract/user-mechanism/shelf-pull.mech.pddl";;
    esac
    pdsketch-plan domains/basis.pddl $P $args --timeout 120 --json $OUT/$n.$cfg.json > $OUT/$n.$cfg.plan 2> $OUT/$n.$cfg.err
    echo "$n $cfg exit=$? $(grep -E '^(solved|unsolved)' $OUT/$n.$cfg.err | cut -c1-60)"
  done
done
