"""The batched environment: scene composition, actions and IK, observations, rewards, terminations, resets,
task selection, episode rollouts and recordings, and the simulator's benchmarks and contact sheets."""
