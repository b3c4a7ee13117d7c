#!/bin/bash
# One piece of the README's rl/ppo=paper run on a lent GPU: resume the 2-core run's newest checkpoint with
# rl.ppo.device=cuda, stop right after the first checkpoint saved once $1 seconds of training have passed, and
# send back that checkpoint (in parts under 16 MiB), the curve, the event file and a filtered log.
#   bash .ppo/run.sh 450 560     # train for 450 s, then to the next checkpoint; stop anyway at 560 s
# .ppo/ (git-ignored) travels with the call: site_rl.tar.xz, the Python 3.12 packages the GPU image lacks
# (rsl-rl-lib 5.5.1, hydra-core 1.3.8, omegaconf 2.3.1, mujoco 4.0.0, tensordict 0.15.3, gymnasium 1.4.0 and
# their pure-Python needs, as this project's venv has them), and run/: the run's newest model_*.pt, its
# config.yaml and curve.json.
export PYTHONUNBUFFERED=1 HF_HUB_OFFLINE=1 WANDB_MODE=disabled MUJOCO_GL=disable HYDRA_FULL_ERROR=1
OUT=${OUT:-/tmp/ppo_out}; RUN=/tmp/ppo_run; BUDGET=${1:-450}; HARD=${2:-560}
mkdir -p "$OUT" "$RUN" /tmp/site
T0=$(date +%s); stamp() { echo "=== [$(( $(date +%s) - T0 )) s] $*"; }
newest() { ls "$RUN"/model_*.pt 2>/dev/null | sed 's/.*model_\([0-9]*\)\.pt/\1/' | sort -n | tail -1; }

stamp setup
tar -C /tmp/site -xJf .ppo/site_rl.tar.xz
export PYTHONPATH=/tmp/site:$PWD
nproc; nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader
python3 -c "import sys, torch, numpy, mujoco, rsl_rl, tensordict, hydra; print(sys.version.split()[0], 'torch', torch.__version__, 'numpy', numpy.__version__, 'mujoco', mujoco.__version__, torch.cuda.get_device_name(0))" || exit 3
cp .ppo/run/* "$RUN"/ && sha256sum "$RUN"/model_*.pt
FIRST=$(newest); stamp "resuming from model_$FIRST.pt"

python3 -m mobilemani_rl.train robot=xhand task.object=laptop/0003 task.skill=close rl/ppo=paper \
  rl.ppo.device=cuda run_dir=$RUN > /tmp/train.log 2>&1 &
PID=$!
START=$(date +%s)
while kill -0 $PID 2>/dev/null && [ $(( $(date +%s) - START )) -lt "$BUDGET" ]; do sleep 2; done
AT=$(newest); stamp "budget reached at model_$AT.pt; waiting for the next checkpoint"
while kill -0 $PID 2>/dev/null && [ "$(newest)" = "$AT" ] && [ $(( $(date +%s) - T0 )) -lt "$HARD" ]; do sleep 1; done
kill -TERM $PID 2>/dev/null; wait $PID; echo "train rc=$?"
LAST=$(newest); stamp "stopped; newest checkpoint model_$LAST.pt"

tr '\r' '\n' < /tmp/train.log | grep -a -v "^\s*$" | awk '/PPO/ { if (++n % 25 == 0) print; next } { print }' > $OUT/train.log
tail -3 $OUT/train.log
sha256sum "$RUN/model_$LAST.pt" | tee -a $OUT/train.log
split -b 15M -d "$RUN/model_$LAST.pt" "$OUT/model_$LAST.pt.part"
cp "$RUN/curve.json" $OUT/curve.json
ls -t "$RUN"/events.out.tfevents.* | head -1 | xargs -I{} cp {} $OUT/
ls -la $OUT; stamp done
