#!/bin/bash
# Issue 40's shared demonstrations: 100 successful scripted ee_delta episodes per task
# (EPISODES, default 100; issue 39's cloning study uses 25, 100 and 400), converted into
# every other mode with `unified-manip convert`. Resumable: a dataset that
# exists is skipped (collect and convert publish under a temporary name, then rename).
# MODES (unset: every other mode; set empty: none) names the modes to convert into. COLLECT names modes to
# record directly instead, the scripted policy in that mode (Meta-World's native: its own
# controller, which convert cannot drive), from the same seed.
# Usage: make_datasets.sh TASK...   (run from a checkout with its .venv; ROOT defaults to ./data, the grid reads data/{task}/{action_mode}-v0)
set -u
ROOT=${ROOT:-data}
EPISODES=${EPISODES:-100}
MODES=${MODES-joint_torque joint_position joint_delta joint_target_delta joint_velocity ee_target_delta native}
COLLECT=${COLLECT:-}
export OMP_NUM_THREADS=1 MUJOCO_GL=egl MINARI_DATASETS_PATH=$ROOT
UM=${UM:-.venv/bin/unified-manip}
for task in "$@"; do
  name=$task
  src=$ROOT/$name/ee_delta-v0
  if [ ! -d "$src" ]; then
    $UM collect --env UnifiedManip/$task --policy scripted --episodes $EPISODES --only-successful --seed 1000000 \
      --action-mode ee_delta --out $src --no-progress --json $ROOT/$name/ee_delta.json || exit 1
  fi
  for mode in $COLLECT; do
    out=$ROOT/$name/$mode-v0
    [ -d "$out" ] && continue
    # A mode whose scripted episodes never succeed is reported and skipped, not fatal.
    $UM collect --env UnifiedManip/$task --policy scripted --episodes $EPISODES --only-successful --seed 1000000 \
      --action-mode $mode --out $out --no-progress --json $ROOT/$name/$mode.json || echo "$task $mode: not collected"
  done
  for mode in $MODES; do
    out=$ROOT/$name/$mode-v0
    [ -d "$out" ] || [ -f $ROOT/$name/$mode.json ] && continue
    # The per-episode table goes to MODE.out; the last line ("wrote ...") is shown.
    if $UM convert $src --action-mode $mode --out $out --no-progress --json $ROOT/$name/$mode.json \
      > $ROOT/$name/$mode.out 2> $ROOT/$name/$mode.err; then
      tail -n 1 $ROOT/$name/$mode.out
    else
      echo "$task $mode: $(tail -1 $ROOT/$name/$mode.err)"
    fi
  done
done
