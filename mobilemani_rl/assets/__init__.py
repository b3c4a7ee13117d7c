"""Procedural MuJoCo assets: robots, objects, and the support stage."""
