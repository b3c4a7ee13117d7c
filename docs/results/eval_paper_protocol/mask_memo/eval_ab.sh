# demo protocol (20 episodes, 1 worker) with the 20-step cpu VLA of ../cpu_2core_rate.sh (/tmp/s20/vlaw): 0e76695 (/tmp/ci21c) vs the working tree
source /tmp/ci21c/.venv/bin/activate
export MUJOCO_GL=egl HF_HUB_OFFLINE=1 WANDB_MODE=disabled
CK=/tmp/s20/vlaw/run/checkpoints/step_00000020
rm -rf /tmp/s22/ab; mkdir -p /tmp/s22/ab
for round in 1 2; do
for side in before after; do
  if [ $side = before ]; then cd /tmp/ci21c; P=; else cd /work/main; P=/work/main; fi
  s=$(date +%s.%N)
  PYTHONPATH=$P python -m mobilemani_vla.evaluate robot=g1 policy.checkpoint=$CK eval/protocol=demo output_dir=/tmp/s22/ab/$side$round name=demo workers=1 > /tmp/s22/ab/$side$round.log 2>&1
  echo "$side round $round rc=$? wall $(python3 -c "import time; print(round(time.time() - $s, 1))") s"
done
done
