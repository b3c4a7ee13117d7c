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

.PHONY: setup test test-slow lint bench bench-sim bench-ppo clean-venv rl tables vla bench-vla eval

setup: $(VENV)/.installed

# Rebuilt only when the dependency list changes.
$(VENV)/.installed: pyproject.toml
	@test -n "$(PYTHON312)" || { echo "error: Python 3.12 not found on PATH or under pyenv"; exit 1; }
	@test -x $(PY) || $(PYTHON312) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev]"
	touch $@

test: setup
	$(PY) -m pytest -q

test-slow: setup
	$(PY) -m pytest -q -m slow

lint: setup
	$(VENV)/bin/ruff check .

# Every benchmark in one JSON (results/bench.json) and one table against the raw MuJoCo limits.
bench: setup
	$(PY) scripts/bench_all.py

bench-sim: setup
	$(PY) -m mobilemani_rl.bench

bench-ppo: setup
	$(PY) -m mobilemani_rl.rl.bench

# PPO teacher (Hydra root conf/rl.yaml), then 256 evaluation episodes:
#   make rl ROBOT=g1 [OBJECT=test/box SKILL=open PPO=cpu|paper]; OBJECT may be a category (multi-object policy)
OBJECT ?= test/box
SKILL ?= open
PPO ?= cpu
rl: setup
	$(PY) -m mobilemani_rl.train robot=$(ROBOT) task.object=$(OBJECT) task.skill=$(SKILL) rl/ppo=$(PPO) \
		eval_episodes=256

tables: setup
	$(PY) scripts/rl_tables.py runs/rl --out results/rl
	$(PY) scripts/vla_tables.py results/eval --out results/vla

# Closed-loop evaluation (Hydra root conf/eval.yaml): make eval ROBOT=g1 CHECKPOINT=<VLA checkpoint dir>
#   [POLICY=vla|lerobot|teacher|scripted|random PROTOCOL=paper|ablation|small SPLIT=unseen_unseen|seen_unseen|.. NAME=..]
POLICY ?= vla
PROTOCOL ?= paper
SPLIT ?= unseen_unseen
eval: setup
	$(PY) -m mobilemani_vla.evaluate robot=$(ROBOT) eval/policy=$(POLICY) eval/protocol=$(PROTOCOL) eval/split=$(SPLIT) \
		$(if $(CHECKPOINT),policy.checkpoint=$(CHECKPOINT)) $(if $(NAME),name=$(NAME))

# VLA training (Hydra root conf/vla.yaml): make vla ROBOT=g1 [EXPERIMENT=ablation_image_head_rgb]
vla: setup
	$(PY) -m mobilemani_vla.train robot=$(ROBOT) $(if $(EXPERIMENT),+experiment=$(EXPERIMENT))

bench-vla: setup
	$(PY) -m mobilemani_vla.bench

# MobileManiDataset (Hydra root conf/data.yaml): collect -> export -> validate -> stats for a subset:
#   make data ROBOT=g1 [SUBSET=small|tiny|train|test TEACHER=scripted|ppo DATA_ARGS='export.width=224 export.height=224']
SUBSET ?= small
TEACHER ?= scripted
DATA_ARGS ?=
DATA_HYDRA = robot=$(ROBOT) data/subset=$(SUBSET) data/teacher=$(TEACHER) $(DATA_ARGS)
.PHONY: data bench-data
data: setup
	$(PY) -m mobilemani_data.collect $(DATA_HYDRA)
	$(PY) -m mobilemani_data.export $(DATA_HYDRA) export.overwrite=true
	$(PY) -m mobilemani_data.validate $(DATA_HYDRA)
	$(PY) -m mobilemani_data.stats $(DATA_HYDRA)

bench-data: setup
	$(PY) -m mobilemani_data.bench robot=$(ROBOT)

clean-venv:
	rm -rf $(VENV)
