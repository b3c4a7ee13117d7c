"""MobileManiRL: simulator, assets, environment, PPO training and evaluation."""

import os

# Headless first: offscreen rendering through EGL unless the user chose a GL backend.
os.environ.setdefault("MUJOCO_GL", "egl")
