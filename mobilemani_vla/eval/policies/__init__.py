"""Policies the closed-loop evaluator can run: one interface (observation dict in, action chunk out)."""
