# MobileManiBench-MuJoCo. `make setup` builds .venv (Python >= 3.12); every other target runs inside it.
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
export MUJOCO_GL ?= egl
export HF_HUB_OFFLINE ?= 1
export WANDB_MODE ?= offline

# Python 3.12: from PATH first, then pyenv.
PYTHON312 ?= $(shell for c in python3.12 $$(pyenv root 2>/dev/null)/versions/3.12*/bin/python3.12; do \
	"$$c" -c 'import sys; assert sys.version_info[:2] == (3, 12)' >/dev/null 2>&1 && { echo "$$c"; break; }; done)

ROBOT ?= g1
# Every output goes under outputs/ by default (the path variables below and the Hydra configs' defaults).

.PHONY: help setup test test-slow lint bench bench-sim bench-ppo clean-venv rl teachers teachers-base-ablation tables vla ablation bench-vla demo eval

setup: $(VENV)/.installed

# One line per target (`make` alone still runs setup).
help:
	@echo "make setup        build .venv (Python 3.12) from pyproject.toml; skipped when up to date"
	@echo "make demo         the whole chain at small scale: teacher, data, VLA, evaluation, report (DEMO, docs/results/demo.md)"
	@echo "make test         the default test suite (pytest, tiny configs)"
	@echo "make test-slow    the slower tests (kill -9 reruns, multi-process training, trained teachers)"
	@echo "make lint         ruff check and ruff format --check"
	@echo "make rl           a PPO teacher for one task, then its evaluation (ROBOT OBJECT SKILL PPO ITERATIONS RL_ARGS)"
	@echo "make teachers     the paper's teacher table, one teacher per category and skill (ROBOT TEACHERS_OUT TEACHER_ARGS)"
	@echo "make teachers-base-ablation  the paper's base-mobility table: six g1 rows, mobile and fixed base (TEACHERS_OUT)"
	@echo "make data         collect, export, validate and describe a LeRobot dataset (ROBOT PRESET SUBSET TEACHER DATA_ARGS)"
	@echo "make vla          train MobileManiVLA (ROBOT EXPERIMENT VLA_ARGS)"
	@echo "make recipe       the CPU VLA recipe end to end: data, VLA, evaluation in unseen rooms (RECIPE_SKILL RECIPE_STEPS)"
	@echo "make lerobot      a stock LeRobot policy on a dataset, then the same evaluation (LEROBOT_POLICY LEROBOT_DATA)"
	@echo "make ablation     the paper's VLA ablation study, resumable: rows trained and evaluated, then tables (ABLATION_ARGS)"
	@echo "make eval         the paper's closed-loop evaluation (ROBOT CHECKPOINT POLICY PROTOCOL SPLIT WORKERS EVAL_ARGS)"
	@echo "make tables       the paper's tables and plots from the results found (RL_RUNS EVAL_RESULTS)"
	@echo "make bench        every benchmark in one JSON (outputs/bench.json) and one table"
	@echo "make bench-sim    the batched simulator against raw MuJoCo"
	@echo "make bench-ppo    PPO training throughput"
	@echo "make bench-data   dataset export throughput: frames/s, rendering share, size per episode (ROBOT)"
	@echo "make bench-vla    VLA training and inference throughput"
	@echo "make clean-venv   remove .venv"
	@echo "make help         this list"
	@echo "Usage and options: docs/usage.md"

# The LeRobot plugins (integrations/): lerobot-eval --env.type=mobilemanibench, lerobot-train --policy.type=mobilemanivla
PLUGINS = integrations/lerobot_env_mobilemanibench integrations/lerobot_policy_mobilemanivla

# Rebuilt only when the dependency list changes. Two `make` calls started together would both find it stale:
# the lock makes the second wait, and the recheck inside it skips the install the first one just finished.
$(VENV)/.installed: pyproject.toml $(addsuffix /pyproject.toml,$(PLUGINS))
	@test -n "$(PYTHON312)" || { echo "error: Python 3.12 not found on PATH or under pyenv"; exit 1; }
	@set -e; exec 9>$(VENV).lock; ! command -v flock >/dev/null || flock 9; \
	if [ -f $@ ] && [ -z "$$(find $^ -newer $@)" ]; then echo "$(VENV) is up to date (installed by another make call)"; exit 0; fi; \
	test -x $(PY) || $(PYTHON312) -m venv $(VENV); \
	echo "installing into $(VENV): PyTorch with its CUDA libraries and the rest, several GB (pip's progress below)"; \
	$(PY) -m pip install --quiet --upgrade pip; \
	$(PY) -m pip install --progress-bar on -e ".[dev]" $(addprefix -e ,$(PLUGINS)); \
	touch $@

test: setup
	$(PY) -m pytest -q

test-slow: setup
	$(PY) -m pytest -q -m slow

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

# Every benchmark in one JSON (outputs/bench.json) and one table against the raw MuJoCo limits.
bench: setup
	$(PY) -m scripts.bench_all

bench-sim: setup
	$(PY) -m mobilemani_rl.envs.bench

bench-ppo: setup
	$(PY) -m mobilemani_rl.rl.bench

# PPO teacher (Hydra root conf/rl.yaml), then 256 evaluation episodes:
#   make rl ROBOT=g1 [OBJECT=test/box SKILL=open PPO=cpu|paper ITERATIONS=300]; OBJECT may be a category (multi-object
#   policy). ITERATIONS empty: the preset's (cpu: a warm start from scripted episodes, then 3000 iterations = 12.3 M
#   samples, what test/can pick needs); test/box open needs ITERATIONS=300. Times: docs/results/throughput.md.
OBJECT ?= test/box
SKILL ?= open
PPO ?= cpu
ITERATIONS ?=
RL_ARGS ?=
rl: setup
	$(PY) -m mobilemani_rl.rl.train robot=$(ROBOT) task.object=$(OBJECT) task.skill=$(SKILL) rl/ppo=$(PPO) \
		$(if $(ITERATIONS),rl.ppo.max_iterations=$(ITERATIONS)) eval_episodes=256 $(RL_ARGS)

# The teacher table: one category-level teacher per category-skill row (39 for g1), each evaluated on the category's
# train and test objects; rows run in turn, a finished row is skipped and an interrupted one resumes, so rerunning
# continues. Results (JSON, per-row and paper tables, Markdown + LaTeX) go to TEACHERS_OUT/<robot>, checkpoints to
# TEACHERS. The results page's records are updated with TEACHERS_OUT=docs/results/teachers (docs/results/teachers.md).
#   make teachers ROBOT=g1 [TEACHER_ARGS="--categories box laptop --skills open"]
TEACHERS ?= outputs/teachers
TEACHERS_OUT ?= outputs/teachers/tables
TEACHER_ITERATIONS ?= 300
# holistic pick is still learning when 300 iterations end, so pick rows get their own count (docs/results/teachers.md)
TEACHER_PICK_ITERATIONS ?= 3000
TEACHER_ARGS ?=
# warm start from 128 scripted episodes per object: the 8 train objects of a row give a single-object run's 1024
teachers: setup
	$(PY) -m mobilemani_rl.rl.sweep --robot $(ROBOT) --runs $(TEACHERS) --out $(TEACHERS_OUT)/$(ROBOT) \
		rl.ppo.max_iterations=$(TEACHER_ITERATIONS) --skill-iterations pick:$(TEACHER_PICK_ITERATIONS) \
		rl.ppo.warm_start.episodes=128 $(TEACHER_ARGS)

# The paper's base-mobility ablation (Table 8): its six G1 rows with a mobile and with a fixed base (env=fixed_base),
# the same budget as `make teachers`, each row evaluated over >= 256 test episodes; rows resume like `make teachers`.
# TEACHER_ARGS here holds Hydra overrides for every row (docs/results/teachers.md: rl.ppo.precision=fp32).
BASE_ABLATION_ROWS = laptop:open cabinet:open faucet:open table:open cart:pull holistic:pick
BASE_ABLATION_OUT = $(TEACHERS_OUT)/g1_base_ablation
teachers-base-ablation: setup
	for base in mobile_base fixed_base; do for row in $(BASE_ABLATION_ROWS); do \
		$(PY) -m mobilemani_rl.rl.sweep --robot g1 --runs $(TEACHERS)/$$base --out $(BASE_ABLATION_OUT)/$$base \
			--categories $${row%:*} --skills $${row#*:} --test-episodes 256 rl.ppo.max_iterations=$(TEACHER_ITERATIONS) \
			--skill-iterations pick:$(TEACHER_PICK_ITERATIONS) rl.ppo.warm_start.episodes=128 \
			$$([ $$base = fixed_base ] && echo env=fixed_base) $(TEACHER_ARGS) || exit 1; \
	done; done
	$(PY) -m mobilemani_rl.rl.base_mobility --mobile $(BASE_ABLATION_OUT)/mobile_base/teachers_g1.json \
		--fixed $(BASE_ABLATION_OUT)/fixed_base/teachers_g1.json --out $(BASE_ABLATION_OUT)

# Tables (Markdown + LaTeX) and bar plots from teacher evaluations and closed-loop results.
RL_RUNS ?= outputs/rl
EVAL_RESULTS ?= outputs/eval
TABLES ?= outputs/tables
MAIN_RUN ?= default
tables: setup
	$(PY) -m mobilemani_rl.rl.tables $(RL_RUNS) --out $(TABLES)/rl
	$(PY) -m mobilemani_rl.rl.base_mobility --mobile $(BASE_ABLATION_OUT)/mobile_base/teachers_g1.json \
		--fixed $(BASE_ABLATION_OUT)/fixed_base/teachers_g1.json --out $(TABLES)/rl
	$(PY) -m mobilemani_vla.eval.tables $(EVAL_RESULTS) --out $(TABLES)/vla --main $(MAIN_RUN)

# Closed-loop evaluation (Hydra root conf/eval.yaml): make eval ROBOT=g1 CHECKPOINT=<VLA checkpoint dir>
#   [POLICY=vla|lerobot|teacher|scripted|random PROTOCOL=paper|ablation|small SPLIT=unseen_unseen|seen_unseen|.. NAME=..
#    WORKERS=<processes running evaluation blocks side by side>]
POLICY ?= vla
PROTOCOL ?= paper
SPLIT ?= unseen_unseen
WORKERS ?= 1
EVAL_ARGS ?=
eval: setup
	$(PY) -m mobilemani_vla.eval.evaluate robot=$(ROBOT) eval/policy=$(POLICY) eval/protocol=$(PROTOCOL) eval/split=$(SPLIT) \
		workers=$(WORKERS) $(if $(CHECKPOINT),policy.checkpoint=$(CHECKPOINT)) $(if $(NAME),name=$(NAME)) $(EVAL_ARGS)

# VLA training (Hydra root conf/vla.yaml): make vla ROBOT=g1 [EXPERIMENT=ablation_image_head_rgb]
VLA_ARGS ?=
vla: setup
	$(PY) -m mobilemani_vla.train robot=$(ROBOT) $(if $(EXPERIMENT),+experiment=$(EXPERIMENT)) $(VLA_ARGS)

# The paper's VLA ablation study (docs/results/ablation.md): every row trained on the ablation dataset and
# evaluated on its protocol, in order, within ABLATION_ARGS' --minutes (default 150); rerun until it says the
# rows are done. Options: python -m mobilemani_vla.ablation_study --help.
ABLATION_ARGS ?=
ablation: setup
	$(PY) -m mobilemani_vla.ablation_study --tables $(TABLES)/vla $(ABLATION_ARGS)

bench-vla: setup
	$(PY) -m mobilemani_vla.bench

# MobileManiDataset (Hydra root conf/data.yaml): collect -> export -> validate -> stats for a subset:
#   make data ROBOT=g1 [PRESET=demo|recipe SUBSET=small|tiny|train|test TEACHER=scripted|ppo
#                       DATA_ARGS='export.width=224 export.height=224']
# PRESET names a whole dataset (conf/data/preset: subset, teacher, export settings). SUBSET and TEACHER reach the
# command line only when set (a group choice there would replace the preset's); unset, conf/data.yaml's apply
# (small, scripted).
PRESET ?=
SUBSET ?=
TEACHER ?=
DATA_ARGS ?=
DATA_HYDRA = $(strip robot=$(ROBOT) $(if $(PRESET),data/preset=$(PRESET)) $(if $(SUBSET),data/subset=$(SUBSET)) \
	$(if $(TEACHER),data/teacher=$(TEACHER)) $(DATA_ARGS))
.PHONY: data bench-data
data: setup
	$(PY) -m mobilemani_data.collect $(DATA_HYDRA)
	$(PY) -m mobilemani_data.export $(DATA_HYDRA) export.overwrite=true
	$(PY) -m mobilemani_data.validate $(DATA_HYDRA)
	$(PY) -m mobilemani_data.stats $(DATA_HYDRA)

bench-data: setup
	$(PY) -m mobilemani_data.bench robot=$(ROBOT)

# The CPU VLA recipe (docs/usage.md, results in docs/results/vla.md): the dataset conf/data/preset/recipe.yaml for
# one skill, the VLA conf/experiment/recipe.yaml trained RECIPE_STEPS steps, 40 closed-loop episodes in the 4 unseen
# test rooms (conf/eval/protocol/recipe.yaml).
#   make recipe [RECIPE_SKILL=open|close RECIPE_STEPS=9000]
RECIPE ?= outputs/recipe
RECIPE_SKILL ?= open
RECIPE_STEPS ?= 9000
RECIPE_DIR = $(RECIPE)/$(RECIPE_SKILL)
.PHONY: recipe
recipe: setup
	$(MAKE) data ROBOT=g1 PRESET=recipe DATA_ARGS="data_dir=$(RECIPE_DIR)/data subset.skills=[$(RECIPE_SKILL)]"
	$(MAKE) vla ROBOT=g1 EXPERIMENT=recipe VLA_ARGS="name=recipe_$(RECIPE_SKILL) data.root=$(RECIPE_DIR)/data/lerobot \
		train.output_dir=$(RECIPE_DIR)/vla train.steps=$(RECIPE_STEPS)"
	$(MAKE) eval ROBOT=g1 POLICY=vla PROTOCOL=recipe NAME=vla_$(RECIPE_SKILL) \
		CHECKPOINT=$(RECIPE_DIR)/vla/checkpoints/step_$(shell printf %08d $(RECIPE_STEPS)) \
		EVAL_ARGS="output_dir=$(RECIPE)/eval subset.skills=[$(RECIPE_SKILL)]"

# A stock LeRobot policy on a MobileManiDataset, unmodified: lerobot-train, then the same closed-loop protocol as
# MobileManiVLA (results land beside it, so `make tables` shows both). Pretrained backbones stay off (no downloads):
#   make lerobot [LEROBOT_POLICY=act|diffusion|smolvla LEROBOT_DATA=outputs/recipe/open/data/lerobot LEROBOT_STEPS=2000
#                 PROTOCOL=recipe EVAL_ARGS="output_dir=outputs/recipe/eval"]
# The default LEROBOT_DATA is `make data`'s dataset, six streams at 520 px: too large for ACT at batch 16 in a CPU
# machine's memory (docs/results/baselines.md). On a CPU give it a dataset exported at 64-128 px (docs/usage.md).
LEROBOT_POLICY ?= act
LEROBOT_DATA ?= outputs/data/$(ROBOT)/lerobot
LEROBOT_STEPS ?= 2000
LEROBOT_BATCH ?= 16
LEROBOT_OUT ?= outputs/lerobot/$(ROBOT)/$(LEROBOT_POLICY)
LEROBOT_ARGS ?=
# The project's CPU settings for each policy type (chunk, sizes, no downloads; SmolVLA from scratch on an untrained
# local SmolVLM backbone, written on first use): `--preset=cpu`, mobilemani_vla/lerobot_presets.py. LEROBOT_ARGS
# flags replace the preset's (e.g. sizes for a GPU).
LEROBOT_LAST = $(LEROBOT_OUT)/checkpoints/last
LEROBOT_TRAIN = HF_HUB_OFFLINE=1 $(PY) -m mobilemani_vla.lerobot_train
# Rerunning continues (mobilemani_vla.lerobot_train): a finished run is skipped, an interrupted one resumes from
# its last checkpoint (saved every quarter of the steps), more LEROBOT_STEPS go on from it; fewer, or another
# policy, dataset or batch size in the same LEROBOT_OUT, are refused by name. The evaluation names the checkpoint
# `last` links to, so results of a run trained on are not mixed with its earlier checkpoint's (it refuses them).
.PHONY: lerobot
lerobot: setup
	$(LEROBOT_TRAIN) --preset=cpu --policy.type=$(LEROBOT_POLICY) --dataset.repo_id=mobilemani/$(ROBOT) \
		--dataset.root=$(LEROBOT_DATA) --batch_size=$(LEROBOT_BATCH) --steps=$(LEROBOT_STEPS) \
		--save_freq=$$(( ($(LEROBOT_STEPS) + 3) / 4 )) --log_freq=50 --output_dir=$(LEROBOT_OUT) $(LEROBOT_ARGS)
	$(MAKE) eval ROBOT=$(ROBOT) POLICY=lerobot NAME=lerobot_$(LEROBOT_POLICY) \
		CHECKPOINT=$$(cd $(LEROBOT_LAST) && pwd -P)/pretrained_model

# The whole chain at small scale (times and results: docs/results/demo.md): a PPO teacher for g1 opening test/box
# (seed DEMO_PPO_SEED, DEMO_PPO_ITERATIONS iterations), its dataset conf/data/preset/demo.yaml (more data
# overrides: DEMO_DATA_ARGS), the VLA conf/experiment/$(DEMO_EXPERIMENT).yaml trained DEMO_VLA_STEPS steps (more VLA
# overrides: DEMO_VLA_ARGS), closed-loop evaluation in the four unseen test rooms
# (conf/eval/protocol/demo.yaml: the teacher over 20 episodes; the VLA over those 20 plus 40 with seed=1, in two
# worker processes, a core each), tables and a report with the VLA's 60-episode rate and its interval,
# DEMO/report.md (no rollout video: it doubles the evaluation on 2 cores; add EVAL_ARGS video_episodes=1 to
# `make eval`).
# Every stage resumes or skips finished work, so a rerun after an interruption continues.
DEMO ?= outputs/demo
DEMO_PPO_SEED ?= 42
DEMO_PPO_ITERATIONS ?= 100
DEMO_EXPERIMENT ?= demo
DEMO_VLA_STEPS ?= 9000
DEMO_DATA_ARGS ?=
DEMO_VLA_ARGS ?=
DEMO_CHECKPOINT = $(DEMO)/vla/checkpoints/step_$(shell printf %08d $(DEMO_VLA_STEPS))
demo: setup
	$(MAKE) rl ROBOT=g1 OBJECT=test/box SKILL=open ITERATIONS=$(DEMO_PPO_ITERATIONS) \
		RL_ARGS="run_dir=$(DEMO)/rl/g1/test/box/open rl.ppo.seed=$(DEMO_PPO_SEED)"
	$(MAKE) data ROBOT=g1 PRESET=demo DATA_ARGS="data_dir=$(DEMO)/data teacher.runs_dir=$(DEMO)/rl $(DEMO_DATA_ARGS)"
	$(MAKE) vla ROBOT=g1 EXPERIMENT=$(DEMO_EXPERIMENT) VLA_ARGS="data.root=$(DEMO)/data/lerobot train.output_dir=$(DEMO)/vla train.steps=$(DEMO_VLA_STEPS) $(DEMO_VLA_ARGS)"
	$(MAKE) eval ROBOT=g1 POLICY=teacher PROTOCOL=demo NAME=teacher \
		EVAL_ARGS="output_dir=$(DEMO)/eval policy.runs_dir=$(DEMO)/rl"
	$(MAKE) eval ROBOT=g1 POLICY=vla PROTOCOL=demo NAME=vla CHECKPOINT=$(DEMO_CHECKPOINT) WORKERS=2 \
		EVAL_ARGS="output_dir=$(DEMO)/eval"
	$(MAKE) eval ROBOT=g1 POLICY=vla PROTOCOL=demo NAME=vla_seed1 CHECKPOINT=$(DEMO_CHECKPOINT) WORKERS=2 \
		EVAL_ARGS="output_dir=$(DEMO)/eval seed=1 subset.episodes=10"
	$(MAKE) tables RL_RUNS=$(DEMO)/rl EVAL_RESULTS=$(DEMO)/eval TABLES=$(DEMO)/tables MAIN_RUN=vla
	$(PY) -m scripts.demo_report $(DEMO)

clean-venv:
	rm -rf $(VENV)
