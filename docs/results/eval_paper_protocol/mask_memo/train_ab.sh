source /tmp/ci21c/.venv/bin/activate
export MUJOCO_GL=egl HF_HUB_OFFLINE=1 WANDB_MODE=disabled
for side in before after; do
  if [ $side = before ]; then cd /tmp/ci21c; P=; else cd /work/main; P=/work/main; fi
  rm -rf /tmp/s22/tr_$side
  s=$(date +%s.%N)
  PYTHONPATH=$P python -m mobilemani_vla.train vla/model=cpu vla/train=cpu data.root=/tmp/s20/vlaw/data data.repo_id=synthetic/g1 data.heldout_episodes=1 \
    train.output_dir=/tmp/s22/tr_$side train.logger=none train.steps=150 train.save_every=150 train.diagnose_every=0 \
    'inputs.cameras=[head_rgb,head_depth,wrist_rgb,wrist_depth]' > /tmp/s22/tr_$side.log 2>&1
  echo "$side rc=$? wall $(python3 -c "import time; print(round(time.time() - $s, 1))") s"
  tr '\r' '\n' < /tmp/s22/tr_$side.log | grep -a "it/s\|s/it" | tail -1
done
