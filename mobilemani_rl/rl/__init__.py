"""PPO teacher training on rsl-rl: configs, runner, run directories."""
