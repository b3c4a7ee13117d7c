"""Rollout digests: equal for equal rollouts, different when anything in the rollout differs."""

import json

from mobilemani_rl.envs import rollout_digest
from mobilemani_rl.envs.rollout_digest import rollout_digest as digest_of


def test_a_digest_repeats_for_the_same_rollout_and_changes_with_its_seed_or_base():
    first = digest_of("g1", fixed_base=False, num_envs=3, steps=12, seed=0)
    assert first == digest_of("g1", fixed_base=False, num_envs=3, steps=12, seed=0)
    assert first != digest_of("g1", fixed_base=False, num_envs=3, steps=12, seed=1)
    assert first != digest_of("g1", fixed_base=True, num_envs=3, steps=12, seed=0)


def test_the_command_prints_one_digest_per_robot_and_base(capsys):
    digests = rollout_digest.main(["--robots", "g1", "--envs", "2", "--steps", "3"])
    assert set(digests) == {"g1 mobile base", "g1 fixed base"}
    assert json.loads(capsys.readouterr().out)["digests"] == digests
