"""Shared utilities of all three packages: input errors and checks, the entry-point wrapper, file and lock
helpers, the worker pool, progress lines, rotations, Hydra config conversion, table formatting."""
