#!/bin/bash
# Run on the device machine as `bash .site/run.sh` from the repository root, with .site/site.tar.xz (the Python
# packages its image lacks, packed from the `make setup` venv) and .site/ckpt (the 20-step `cpu` VLA checkpoint made by
# ../cpu_2core_rate.sh, without its optimizer state). This is the second call; the first ran, in place of A and B:
#   A: w1_cuda 130 workers=1 policy.device=cuda subset.categories=[box] subset.objects_per_category=1 subset.scenes_per_object=2
#   B: w16_cuda 200 workers=16 policy.device=cuda subset.categories=[box,laptop]
#   C: w16_cpu 160 workers=16 policy.device=cpu subset.categories=[box]
# Evaluation workers on one GPU node: rates of `python -m mobilemani_vla.evaluate` with 1 and 16 workers.
set -x
T0=$(date +%s); stamp() { echo "=== [$(( $(date +%s) - T0 )) s] $*"; }
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
if [ -f /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ] && ! ls /usr/share/glvnd/egl_vendor.d/*nvidia* >/dev/null 2>&1; then
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
mkdir -p /tmp/site && tar -C /tmp/site -xJf .site/site.tar.xz
export PYTHONPATH=/tmp/site:$PWD MUJOCO_GL=egl HF_HUB_OFFLINE=1 WANDB_MODE=disabled PYTHONUNBUFFERED=1 HYDRA_FULL_ERROR=1
stamp setup; nproc; nvidia-smi -L; lscpu | grep -i "model name"
python3 -c "import torch, mujoco, transformers, hydra; print(torch.__version__, mujoco.__version__, transformers.__version__, torch.cuda.is_available())"
python3 -c "import mujoco; m = mujoco.MjModel.from_xml_string('<mujoco/>'); r = mujoco.Renderer(m); from OpenGL import GL; print('GL', GL.glGetString(GL.GL_RENDERER))"
E="python3 -m mobilemani_vla.evaluate robot=g1 policy.checkpoint=.site/ckpt output_dir=/tmp/ev subset.skills=[open]"
run() { name=$1; shift; s=$(date +%s.%N); timeout $1 $E name=$name "${@:2}" > $OUT/$name.log 2>&1; rc=$?
  echo "$name rc=$rc wall $(python3 -c "import time; print(round(time.time() - $s, 1))") s" | tee -a $OUT/times.txt; tail -3 $OUT/$name.log; }
stamp A; run w8_cuda 140 workers=8 policy.device=cuda subset.categories=[box]
stamp B; run w16_cuda_box 140 workers=16 policy.device=cuda subset.categories=[box]
nvidia-smi --query-gpu=name,memory.used,memory.total --format=csv
stamp done
