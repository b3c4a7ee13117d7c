#!/bin/bash
# `make teachers ROBOT=g1` on one lent GPU node, stopped after SWEEP_SECONDS (docs/results/gpu_ppo.md): the same
# sweep and settings, its 20 categories as 20 sweeps side by side, PPO's networks on CUDA (rl.ppo.device=cuda) and
# each sweep's physics on one thread (env.physics.nthread=1), so that 20 processes share the 16 cores:
#   OUT=<dir> bash docs/results/gpu_ppo/teachers_parallel.sh 2>&1 | tee $OUT/run_log.txt
# Expects the project's RL dependencies that the node lacks as wheels in .whl/ (it has torch, no network).
export PYTHONUNBUFFERED=1 HF_HUB_OFFLINE=1 WANDB_MODE=disabled MUJOCO_GL=disable
OUT=${OUT:-/tmp/teachers_gpu_out}; SITE=/tmp/site; WORK=/tmp/teachers_gpu; SWEEP_SECONDS=${SWEEP_SECONDS:-480}
mkdir -p "$OUT" "$SITE" "$WORK/logs"
T0=$(date +%s)
stamp() { echo "=== [$(( $(date +%s) - T0 )) s] $*"; }

stamp setup
nproc; export OMP_NUM_THREADS=1  # after nproc, which reports OMP_NUM_THREADS when it is set
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader
python3 docs/results/gpu_ppo/unpack_wheels.py "$SITE" .whl
export PYTHONPATH=$SITE:$PWD
python3 -c "import sys, torch, numpy, mujoco, rsl_rl; print(sys.version.split()[0], 'torch', torch.__version__, \
'numpy', numpy.__version__, 'mujoco', mujoco.__version__, 'cuda', torch.cuda.get_device_name(0))"

CATEGORIES=$(python3 -c "from mobilemani_rl.teacher_sweep import rows; print(*dict.fromkeys(c for c, _ in rows()))")
stamp "20 sweeps side by side, at most $SWEEP_SECONDS s each: $CATEGORIES"
for category in $CATEGORIES; do
  timeout -s INT -k 20 "$SWEEP_SECONDS" python3 -m mobilemani_rl.teacher_sweep --robot g1 --runs "$WORK/runs" \
    --out "$WORK/tables/$category" rl.ppo.max_iterations=300 \
    rl.ppo.warm_start.episodes=128 rl.ppo.device=cuda env.physics.nthread=1 --categories "$category" \
    > "$WORK/logs/$category.log" 2>&1 &
done
wait
stamp "sweeps ended"
for category in $CATEGORIES; do
  echo "--- $category"; tr '\r' '\n' < "$WORK/logs/$category.log" | grep -a -E "^\[row |^error:|PPO.*300/300" | tail -6
done

cat "$WORK/logs"/*.log | tr '\r' '\n' | grep -a -v "^\s*$" | awk '/PPO|Warm|warm/ { if (++n % 200 == 0) print; next } { print }' \
  > "$OUT/logs.txt"
stamp done
