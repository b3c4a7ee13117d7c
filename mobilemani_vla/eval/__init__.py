"""Closed-loop evaluation of any policy (VLA, LeRobot, teacher, scripted, random): config, harness,
observations, policies, results and the paper's tables."""
