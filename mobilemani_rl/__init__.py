"""MobileManiRL: simulator, assets, environment, PPO training and evaluation."""
