#!/bin/bash
# Waits for the benchmark (90 lines in trials.jsonl), then plans each test instance, one run at a time.
cd /work/main
while [ "$(wc -l < /work/runs/s72/final-t1/trials.jsonl)" -lt 90 ]; do
  echo "$(date +%T) $(wc -l < /work/runs/s72/final-t1/trials.jsonl) lines; waiting" >> results/anchors-shelf/wait.log
  sleep 60
done
echo "$(date +%T) benchmark done: $(wc -l < /work/runs/s72/final-t1/trials.jsonl) lines" >> results/anchors-shelf/wait.log
M=problems/contract/user-mechanism/shelf-pull.mech.pddl
for N in 0 1 2 3 4 5 6 7 8 9; do
  for V in anchored generic basis; do
    case $V in anchored) X="";; generic) X="--no-learned-samplers";; basis) X="--basis-only";; esac
    CMD=".venv/bin/python -m pdsketch_mech.plan basis results/anchors-shelf/test-$N.pddl --mechanisms $M --timeout 120 $X --json results/anchors-shelf/$V-$N.json"
    S=$(date +%s.%N)
    $CMD > results/anchors-shelf/$V-$N.log 2>&1
    RC=$?
    E=$(date +%s.%N)
    echo "$N $V rc=$RC wall=$(echo "$E - $S" | bc) :: $CMD" >> results/anchors-shelf/runs.log
  done
done
echo done >> results/anchors-shelf/runs.log
