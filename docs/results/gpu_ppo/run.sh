#!/bin/bash
# PPO with rl.ppo.device=cuda on a lent GPU machine, one script (docs/results/gpu_ppo.md):
#   bash docs/results/gpu_ppo/run.sh 2>&1 | tee $OUT/log.txt
# Expects the project's RL dependencies as wheels in runs/gpu_wheels/ (the machine has torch, no network);
# only the distributions the machine lacks are unpacked, ahead of nothing it has.
export PYTHONUNBUFFERED=1 HF_HUB_OFFLINE=1 WANDB_MODE=disabled MUJOCO_GL=disable HYDRA_FULL_ERROR=1
OUT=${OUT:-/tmp/gpu_ppo_out}; W=/tmp/gpu_ppo_work; SITE=/tmp/site
mkdir -p "$OUT" "$W" "$SITE"
T0=$(date +%s)
stamp() { echo "=== [$(( $(date +%s) - T0 )) s] $*"; }

stamp setup
nproc; nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv
python3 docs/results/gpu_ppo/unpack_wheels.py "$SITE" runs/gpu_wheels
export PYTHONPATH=$SITE:$PWD
python3 -c "import sys, torch, numpy, mujoco, rsl_rl, cv2; print(sys.version.split()[0], 'torch', torch.__version__, 'numpy', numpy.__version__, 'mujoco', mujoco.__version__, 'cuda', torch.cuda.get_device_name(0))"

stamp "1. pytest: PPO on each device, bf16 collection, bad devices"
timeout 120 python3 -m pytest -q -p no:cacheprovider tests/test_rl_training.py -k "device or precision" 2>&1 | tail -5

stamp "2. bench: cpu and paper presets, PPO networks on the CPU vs on CUDA, same run"
timeout 180 python3 -m mobilemani_rl.rl.bench --presets cpu paper --robots g1 --iterations 5 \
  --variants - "rl.ppo.device=cuda" 2>&1 | grep -v "^PPO" | tee $OUT/bench.txt | tail -12

stamp "3. the README's rl/ppo=paper example with rl.ppo.device=cuda (stopped at 120 s: its rate and ETA)"
timeout 120 python3 -m mobilemani_rl.train robot=xhand task.object=laptop/0003 task.skill=close rl/ppo=paper \
  rl.ppo.device=cuda run_dir=$W/paper_cuda 2>&1 | tr '\r' '\n' | grep -a "PPO" | awk 'NR % 20 == 0' | tail -8
cp $W/paper_cuda/curve.json $OUT/paper_cuda_curve.json 2>/dev/null

stamp "4. g1 test/box open, cpu preset, 300 iterations on CUDA, then 256 evaluation episodes (the README's row)"
timeout 260 python3 -m mobilemani_rl.train robot=g1 task.object=test/box task.skill=open rl/ppo=cpu \
  rl.ppo.max_iterations=300 rl.ppo.device=cuda eval_episodes=256 run_dir=$W/box_cuda 2>&1 | tr '\r' '\n' \
  | grep -a -v "^\s*$" | awk '/PPO/ { if (++n % 50 == 0) print; next } { print }' | tail -15
for f in $W/box_cuda/*.json; do cp "$f" "$OUT/box_cuda_$(basename "$f")"; done
stamp done
