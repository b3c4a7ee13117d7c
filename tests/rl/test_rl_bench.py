"""The PPO benchmark: samples/s against the raw physics limit, and where an iteration's time goes."""

from mobilemani_rl.rl.bench import ITERATION_PARTS, bench_preset


def test_ppo_bench_splits_its_iterations_into_update_inference_and_env_step():
    result = bench_preset("cpu", "g1", 2, "rl.ppo.num_envs=8 rl.ppo.num_steps_per_env=4")
    shares = result["iteration_shares"]
    assert tuple(shares) == ITERATION_PARTS
    assert all(share > 0 for share in shares.values()) and sum(shares.values()) <= 1.0
    assert result["samples_per_s"] > 0 and result["ppo_over_raw"] > 0
