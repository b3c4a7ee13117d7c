"""PPO teachers on rsl-rl: configs, runner, warm start, run directories, the train and eval entry points, the
teacher sweep and tables, and the PPO benchmark."""
