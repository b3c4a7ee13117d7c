#!/bin/bash
# GPU-path run (device machine): bash .gpu/run.sh 2>&1 | tee $OUT/log.txt
# Local rehearsal: DEV=cpu SITE=/tmp/site_build EXTRA_PATH=/tmp/devbase PY=python3.12 STEPS_A=3 ... bash .gpu/run.sh
set -x
export HYDRA_FULL_ERROR=1 PYTHONUNBUFFERED=1 HF_HUB_OFFLINE=1 WANDB_MODE=disabled MUJOCO_GL=egl TOKENIZERS_PARALLELISM=false
OUT=${OUT:-/tmp/gpu_out}
DEV=${DEV:-cuda}
PY=${PY:-python3}
STEPS_A=${STEPS_A:-50}
STEPS_B=${STEPS_B:-20}
EPLEN=${EPLEN:-300}
W=${WORK:-/tmp/gpuwork}
rm -rf "$W"; mkdir -p "$W" "$OUT"
T0=$(date +%s)
stamp() { echo "=== [$(( $(date +%s) - T0 )) s] $*"; }

stamp setup
date -u; uname -a; nproc
nvidia-smi || true
ldconfig -p | grep -E 'libEGL|libGL\.so|libOpenGL' || true
if [ "$DEV" = cuda ] && ! ldconfig -p | grep -q 'libEGL.so.1 '; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
  ldconfig -p | grep -E 'libEGL|libOpenGL' || true
fi
ls /usr/share/glvnd/egl_vendor.d/ /usr/local/nvidia/share/glvnd/egl_vendor.d/ 2>/dev/null || true
if [ "$DEV" = cuda ] && [ -f /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ] && ! ls /usr/share/glvnd/egl_vendor.d/*nvidia* >/dev/null 2>&1; then
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
if [ -z "$SITE" ]; then
  SITE=/tmp/site; mkdir -p $SITE
  (tar -C $SITE -xJf .gpu/site_pack.tar.xz || $PY -c "import tarfile; tarfile.open('.gpu/site_pack.tar.xz').extractall('$SITE')")
fi
export PYTHONPATH=$SITE:$PWD${EXTRA_PATH:+:$EXTRA_PATH}
$PY -c "import sys, torch, transformers, tokenizers, accelerate, numpy, pandas, mujoco, av, lerobot, diffusers, hydra; print(sys.version); print({m.__name__: getattr(m, '__version__', '?') for m in (torch, transformers, tokenizers, accelerate, numpy, pandas, mujoco, av, lerobot, diffusers, hydra)}); print('cuda', torch.cuda.is_available(), torch.version.cuda, torch.cuda.get_device_name(0) if torch.cuda.is_available() else None)"

stamp "1. pytest tests/test_vla_gpu_paths.py"
[ -n "$SKIP_PYTEST" ] || timeout 120 $PY -m pytest -x -q -p no:cacheprovider --durations=5 tests/test_vla_gpu_paths.py

stamp "2. synthetic dataset"
timeout 60 $PY .gpu/gpu_paths.py data $W/data

stamp "3. python -m mobilemani_vla.train (single process, bf16, $STEPS_A steps, EMA, held-out diagnostics)"
time timeout 120 $PY -m mobilemani_vla.train vla/model=tiny data.root=$W/data data.repo_id=synthetic/g1 \
  data.heldout_episodes=1 train.output_dir=$W/runA train.logger=none train.progress=true train.batch_size=32 \
  train.steps=$STEPS_A train.mixed_precision=bf16 train.log_every=10 train.diagnose_every=25 train.save_every=25 \
  2>&1 | tr '\r' '\n'
cp $W/runA/last_run.json $OUT/runA_last_run.json; cp $W/runA/diagnostics.jsonl $OUT/runA_diagnostics.jsonl
ls -la $W/runA/checkpoints/*
CKA=$(ls -d $W/runA/checkpoints/step_* | tail -1)

stamp "4. VLAEvalPolicy on $DEV from the bf16 checkpoint"
timeout 90 $PY .gpu/gpu_paths.py policy $DEV $OUT/gpu_paths.json $CKA

stamp "5. in-process bf16 probe (autocast dtypes) + bfloat16 backbone on $DEV"
timeout 90 $PY .gpu/gpu_paths.py probe $W/data $DEV $OUT/gpu_paths.json

if [ "$DEV" = cuda ]; then
  stamp "6. accelerate launch --num_processes 1 --use_fsdp (paper recipe: bf16, grad checkpointing, no EMA)"
  time timeout 120 $PY -m accelerate.commands.launch --num_processes 1 --num_machines 1 \
    --use_fsdp --fsdp_state_dict_type FULL_STATE_DICT --mixed_precision bf16 --dynamo_backend no \
    -m mobilemani_vla.train vla/model=tiny vla/train=paper data.root=$W/data data.repo_id=synthetic/g1 \
    data.heldout_episodes=1 train.output_dir=$W/runB train.logger=none train.progress=true train.batch_size=32 \
    train.steps=$STEPS_B train.save_every=10 train.log_every=10 train.diagnose_every=0 2>&1 | tr '\r' '\n'
  ls -la $W/runB/checkpoints/* || true
  CKB=$(ls -d $W/runB/checkpoints/step_* 2>/dev/null | tail -1)
  [ -n "$CKB" ] && timeout 60 $PY .gpu/gpu_paths.py policy $DEV $OUT/gpu_paths.json $CKB
fi

stamp "8. closed-loop evaluation on $DEV (demo protocol, 1 scene, 2 episodes of $EPLEN steps, EGL)"
time timeout 120 $PY -m mobilemani_vla.evaluate robot=g1 policy.checkpoint=$CKA policy.device=$DEV \
  eval/protocol=demo subset.episodes=2 subset.scenes_per_object=1 env.episode_length=$EPLEN \
  output_dir=$W/eval name=gpu
cp $W/eval/g1/gpu/*.summary.json $OUT/ 2>/dev/null; cp $W/eval/g1/gpu/*.jsonl $OUT/eval_episodes.jsonl 2>/dev/null

if [ "$DEV" = cuda ]; then
  stamp "9. accelerate launch --use_fsdp with the CPU recipe's EMA and held-out diagnostics (4 steps)"
  timeout 90 $PY -m accelerate.commands.launch --num_processes 1 --num_machines 1 \
    --use_fsdp --fsdp_state_dict_type FULL_STATE_DICT --mixed_precision bf16 --dynamo_backend no \
    -m mobilemani_vla.train vla/model=tiny data.root=$W/data data.repo_id=synthetic/g1 \
    data.heldout_episodes=1 train.output_dir=$W/runC train.logger=none train.progress=false train.batch_size=32 \
    train.steps=4 train.save_every=2 train.diagnose_every=2 train.mixed_precision=bf16 2>&1
  ls -la $W/runC/checkpoints/* || true
fi
nvidia-smi --query-gpu=name,memory.used,memory.total --format=csv || true
stamp done
