"""The VLA's training data: the dataset reader, the decoded-frame cache, augmentation, LeRobot's reader served
from the cache, and a synthetic dataset for tests and benchmarks."""
