#!/bin/bash
# Two writers of one output at once, on the code in $1 (a clone after `make setup`), under $2:
# RL training, data collection, export, VLA training. Usage: bash concurrent.sh <clone> <scratch dir>
repo=$1; w=$2; rm -rf "$w"; mkdir -p "$w"; cd "$repo" || exit 1
PY=${PY:-$repo/.venv/bin/python}  # the environment `make setup` built
export MUJOCO_GL=egl HF_HUB_OFFLINE=1 WANDB_MODE=offline PYTHONPATH=$repo
pair() {  # name, delay, command...: A starts, B starts `delay` s later with the same command
  local name=$1 delay=$2; shift 2
  ( "$@" > "$w/${name}_a.log" 2>&1; echo "rc=$?" >> "$w/${name}_a.log" ) &
  sleep "$delay"
  "$@" > "$w/${name}_b.log" 2>&1; echo "rc=$?" >> "$w/${name}_b.log"
  wait
  echo "== $name: A $(tail -1 $w/${name}_a.log), B $(tail -1 $w/${name}_b.log)"; grep -h "^error\|Error\|error:" "$w/${name}_a.log" "$w/${name}_b.log" | tail -3 | cut -c1-300
}
pair rl 8 $PY -m mobilemani_rl.train rl/ppo=tiny rl.ppo.max_iterations=3000 rl.ppo.save_interval=500 eval_episodes=0 run_dir=$w/rl
ls "$w/rl"; $PY -c "import json,sys; c=json.load(open('$w/rl/curve.json')); it=[r['iteration'] for r in c]; print('curve rows', len(it), 'distinct', len(set(it)))"
D="data/subset=tiny subset.objects=[dishwasher/0000] subset.episodes=6 collect.num_envs=8 export.width=64 export.height=64 export.vcodec=h264 data_dir=$w/data"
C="data/subset=tiny subset.objects=[dishwasher/0000] subset.episodes=40 collect.num_envs=8 data_dir=$w/collect"
pair collect 7 $PY -m mobilemani_data.collect $C
ls "$w/collect/raw/g1/dishwasher/0000/"*
$PY -m mobilemani_data.collect $D > "$w/collect_for_export.log" 2>&1
pair export 8 $PY -m mobilemani_data.export $D
ls "$w/data"; $PY -m mobilemani_data.validate $D 2>&1 | tail -2
V="vla/model=tiny vla/train=cpu data.root=$w/data/lerobot data.repo_id=mobilemani/g1 data.heldout_episodes=0 train.steps=1000 train.save_every=500 train.diagnose_every=0 train.logger=none train.progress=false train.batch_size=4 train.output_dir=$w/vla"
pair vla 25 $PY -m mobilemani_vla.train $V
ls "$w/vla" "$w/vla/checkpoints"
