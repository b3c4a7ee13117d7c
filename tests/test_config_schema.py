"""Every YAML preset composes with its root against the dataclass schemas and converts to its dataclass."""

import shutil
from pathlib import Path

import pytest
from checkout import ROOT
from hydra import compose, initialize_config_dir
from hydra.errors import ConfigCompositionException
from omegaconf import OmegaConf
from omegaconf.errors import ConfigKeyError

from mobilemani_data.config import DataCfg
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.rl.config import EvalRlCfg, PpoCfg, RLCfg
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_vla.config import ROOT_ONLY, VLACfg
from mobilemani_vla.eval.config import EvalCfg

CONF = ROOT / "conf"

# Each root's conversion, as its entry points do it.
CONVERT = {
    "rl": lambda cfg: to_dataclass(cfg, RLCfg).env_cfg(),
    "eval_rl": lambda cfg: to_dataclass(cfg, EvalRlCfg),
    "data": lambda cfg: to_dataclass(with_env_task(cfg), DataCfg).check(),
    "vla": lambda cfg: to_dataclass(cfg, VLACfg, ignore=ROOT_ONLY).validate(),
    "eval": lambda cfg: to_dataclass(with_env_task(cfg), EvalCfg).check(),
}
# The roots each config group is composed into.
GROUP_ROOTS = {
    "robot": ("rl", "data", "vla", "eval"),
    "env": ("rl", "data", "eval"),
    "rl/ppo": ("rl",),
    "data/subset": ("data",),
    "data/teacher": ("data",),
    "data/preset": ("data",),
    "vla/model": ("vla",),
    "vla/train": ("vla",),
    "eval/policy": ("eval",),
    "eval/protocol": ("eval",),
    "eval/split": ("eval",),
}


def compose_root(root: str, overrides: list[str], conf: Path = CONF):
    with initialize_config_dir(config_dir=str(conf), version_base="1.3"):
        return compose(config_name=root, overrides=overrides)


def preset_cases() -> list[tuple[str, str]]:
    cases = [
        (root, f"{group}={path.stem}")
        for group, roots in GROUP_ROOTS.items()
        for path in sorted((CONF / group).glob("*.yaml"))
        for root in roots
    ]
    cases += [("vla", f"+experiment={path.stem}") for path in sorted((CONF / "experiment").glob("*.yaml"))]
    return cases + [(root, "") for root in CONVERT]


def test_every_group_is_covered():
    groups = {str(p.parent.relative_to(CONF)) for p in CONF.glob("*/**/*.yaml")}
    assert groups - {"experiment", "hydra/launcher"} == set(GROUP_ROOTS)


@pytest.mark.parametrize(("root", "override"), preset_cases())
def test_preset_composes_and_converts(root, override):
    CONVERT[root](compose_root(root, [override] if override else []))


def test_a_data_preset_chooses_its_groups_and_the_command_line_still_wins():
    demo = to_dataclass(with_env_task(compose_root("data", ["data/preset=demo"])), DataCfg)
    assert demo.subset.objects == ["test/box"] and demo.teacher.kind == "ppo"  # its groups beat data.yaml's
    assert demo.collect.action_noise == 0.3 and demo.export.modalities == ["rgb", "seg"]
    assert demo.export.workers == 2 and demo.export.combinations_per_part == 8  # two parts, one per core
    recipe = compose_root("data", ["data/preset=recipe", "data/subset=tiny", "export.width=32"])
    assert recipe.teacher.kind == "scripted" and recipe.subset.episodes == 2 and recipe.export.width == 32


def test_the_demo_experiment_saves_and_diagnoses_at_its_last_step():
    cfg = CONVERT["vla"](compose_root("vla", ["+experiment=demo", "train.steps=40"]))
    assert cfg.name == "demo" and cfg.model.name == "cpu" and cfg.inputs.states == ["wrist_pose"]
    assert cfg.inputs.cameras == ["head_seg", "wrist_rgb", "wrist_seg"]
    assert cfg.train.steps == cfg.train.save_every == cfg.train.diagnose_every == 40
    rgb = CONVERT["vla"](compose_root("vla", ["+experiment=demo_rgb"]))  # RGB and the exact grasp point
    assert rgb.inputs.cameras == ["head_rgb", "wrist_rgb"]
    assert rgb.inputs.states == ["wrist_pose", "grasp_point"]
    assert rgb.train.steps == rgb.train.save_every == 9000 and rgb.train.batch_size == cfg.train.batch_size


@pytest.mark.parametrize("preset", sorted(p.stem for p in (CONF / "rl/ppo").glob("*.yaml")))
def test_ppo_preset_keys_are_ppo_cfg_fields(preset):
    raw = OmegaConf.load(CONF / "rl/ppo" / f"{preset}.yaml")
    OmegaConf.merge(OmegaConf.structured(PpoCfg), raw)  # raises on a key PpoCfg lacks
    composed = to_dataclass(compose_root("rl", [f"rl/ppo={preset}"]), RLCfg).rl.ppo
    assert composed == OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(PpoCfg), raw))


def test_paper_ppo_preset_is_the_dataclass_default():
    paper = to_dataclass(compose_root("rl", ["rl/ppo=paper"]), RLCfg).rl.ppo
    # compared as configs: OmegaConf turns noise_std_range's tuple into a list
    assert OmegaConf.structured(paper) == OmegaConf.structured(PpoCfg())


def test_a_typo_on_the_command_line_is_refused_by_name():
    with pytest.raises(ConfigCompositionException, match="substepz"):
        compose_root("rl", ["env.physics.substepz=4"])
    with pytest.raises(ConfigKeyError, match="no_such_key"):
        CONVERT["data"](compose_root("data", ["+export.no_such_key=1"]))


def test_a_typo_in_a_preset_is_refused_by_name(tmp_path):
    conf = tmp_path / "conf"
    shutil.copytree(CONF, conf)
    (conf / "rl/ppo/typo.yaml").write_text("num_env: 8\n")
    with pytest.raises(ConfigCompositionException) as err:
        compose_root("rl", ["rl/ppo=typo"], conf)
    assert "num_env" in f"{err.value} {err.value.__cause__}"


def test_a_typo_in_a_saved_run_config_is_refused_by_name():
    with pytest.raises(ConfigKeyError, match="objects_per_polcy"):
        to_dataclass({"objects_per_polcy": 3}, RLCfg)
