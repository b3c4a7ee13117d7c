"""MobileManiRL: the simulator (assets, envs, render, the scripted policy), the PPO teachers (rl) and the
utilities all three packages share (utils)."""
