#!/bin/bash
# The held-out run of one of the users' tricks in problems/tricks/NAME, from a checkout:
#   bash results/tricks/commands.sh NAME [PARTS]      # PARTS: any of anchored learned basis (default: all)
# Ten test instances, 120 s each, planner seed 0: the mechanism with its demonstration's anchors
# and no self-play (NAME/anchored-only/: the fragment and anchors as `learn extract` wrote them),
# the same after `learn train` (the fragment as committed, naming its checkpoint), and the basis
# operators alone. Each part prints a table and writes NAME/PART.json.
set -e
NAME=$1; shift
PARTS=${*:-anchored learned basis}
OUT=results/tricks/$NAME
TRICK=problems/tricks/$NAME
PY=${PY:-python}
mkdir -p $OUT/instances
for i in 0 1 2 3 4 5 6 7 8 9; do
  $PY -m pdsketch_mech.envs $TRICK/$NAME.dist.json --split test --seed $i > $OUT/instances/test-$i.pddl
done
for part in $PARTS; do
  case $part in
    anchored) domain=$OUT/anchored-only/$NAME.mech.pddl; json=anchored-only ;;
    learned) domain=$TRICK/$NAME.mech.pddl; json=learned ;;
    basis) domain=domains/basis.pddl; json=basis ;;
  esac
  $PY -m pdsketch_mech.bench plan $domain $OUT/instances/*.pddl --seeds 1 --timeout 120 --json $OUT/$json.json | tee $OUT/$json.txt
done
