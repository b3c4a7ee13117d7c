"""The demo report names what its VLA read, from the checkpoint's config, and how much its images count."""

from pathlib import Path

import pytest
from omegaconf import OmegaConf

from scripts.demo_report import inputs_lines, open_loop_errors, open_loop_lines


def write_checkpoint_config(demo: Path, states: list[str], noise: float) -> None:
    folder = demo / "vla" / "checkpoints" / "step_00000010"
    folder.mkdir(parents=True)
    inputs = {"cameras": ["head_rgb", "wrist_rgb"], "states": states, "grasp_point_noise": noise}
    OmegaConf.save(OmegaConf.create({"inputs": inputs}), folder / "config.yaml")


@pytest.mark.parametrize(
    ("states", "noise", "grasp_line"),
    [
        (["wrist_pose", "grasp_point"], 0.0, "exact"),
        (["wrist_pose", "grasp_point"], 0.04, "off by N(0, (4 cm)^2)"),
        (["wrist_pose"], 0.0, None),
    ],
)
def test_the_report_says_which_states_and_how_exact_the_grasp_point(
    tmp_path: Path, states: list[str], noise: float, grasp_line: str | None
) -> None:
    write_checkpoint_config(tmp_path, states, noise)
    lines = inputs_lines(tmp_path)
    assert lines[0] == f"- inputs: cameras head_rgb, wrist_rgb; states {', '.join(states)}"
    if grasp_line is None:
        assert len(lines) == 1
    else:
        assert len(lines) == 2 and grasp_line in lines[1]


def test_no_checkpoint_no_lines(tmp_path: Path) -> None:
    assert inputs_lines(tmp_path) == []


def test_the_open_loop_gap_is_reported_only_where_both_errors_were_logged() -> None:
    logged = {
        "noise_mse/image": 0.03,
        "open_loop_mse/cfg_1": 0.071,
        "open_loop_mse/cfg_1.5": 0.057,  # the default guidance scale: the one the VLA acts with
        "open_loop_mse/null_image": 0.299,
    }
    assert open_loop_errors(logged) == (1.5, 0.057, 0.299)
    assert "(+0.242)" in open_loop_lines(logged)[-1] and "guidance 1.5" in open_loop_lines(logged)[-1]
    older = {"noise_mse/image": 0.03, "open_loop_mse/cfg_1.5": 0.057}  # before the null vector's was logged
    assert open_loop_errors(older) is None and open_loop_lines(older) == []
