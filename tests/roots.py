"""Root configs composed as their entry points compose them, for tests that build configs directly."""

from checkout import ROOT
from hydra import compose, initialize_config_dir
from omegaconf import DictConfig


def compose_root(name: str, overrides: list[str]) -> DictConfig:
    """The composed root config `name`; importing the config modules registers the roots' schemas, so a test
    run alone composes as in the whole suite."""
    import mobilemani_rl.rl.config  # noqa: F401
    import mobilemani_vla.eval.config  # noqa: F401

    with initialize_config_dir(config_dir=str(ROOT / "conf"), version_base="1.3"):
        return compose(config_name=name, overrides=overrides)
