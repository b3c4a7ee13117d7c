set -e
# The 2-core run of docs/results/eval_paper_protocol.md: a 20-step `cpu` VLA (head + wrist RGB-D, 128 px synthetic
# dataset), then the demo protocol (20 episodes) with 1 and with 2 workers. /tmp/w is a clone with `make setup` done.
cd /tmp/w
source .venv/bin/activate
export MUJOCO_GL=egl HF_HUB_OFFLINE=1 WANDB_MODE=disabled PYTHONUNBUFFERED=1
W=/tmp/s20/vlaw
rm -rf $W; mkdir -p $W
python -c "from pathlib import Path; from mobilemani_vla.synthetic import write_synthetic_dataset; write_synthetic_dataset(Path('$W/data'), episodes=4, length=30, height=128, width=128)"
python -m mobilemani_vla.train vla/model=cpu vla/train=cpu data.root=$W/data data.repo_id=synthetic/g1 data.heldout_episodes=1 \
  train.output_dir=$W/run train.logger=none train.steps=20 train.save_every=20 train.diagnose_every=0 train.progress=false \
  'inputs.cameras=[head_rgb,head_depth,wrist_rgb,wrist_depth]' 2>&1 | tail -3
CK=$(ls -d $W/run/checkpoints/step_* | tail -1)
echo "checkpoint $CK"
for w in ${WORKER_LIST:-1 2}; do
  s=$(date +%s.%N)
  python -m mobilemani_vla.evaluate robot=g1 policy.checkpoint=$CK eval/protocol=demo output_dir=$W/eval name=w$w workers=$w 2>&1 | tail -4
  echo "workers=$w wall $(echo "$(date +%s.%N) - $s" | bc) s"
done
