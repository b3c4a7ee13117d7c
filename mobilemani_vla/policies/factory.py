"""Build the evaluation policy a PolicyCfg names; model stacks are imported only when used."""

from __future__ import annotations

from mobilemani_rl.registry import InputError, check_choice
from mobilemani_vla.eval_config import PolicyCfg
from mobilemani_vla.policies.base import EvalPolicy

KINDS = ("vla", "lerobot", "teacher", "scripted", "random")


def build_policy(cfg: PolicyCfg) -> EvalPolicy:
    check_choice(cfg.kind, KINDS, "policy kind")
    if cfg.kind in ("vla", "lerobot") and not cfg.checkpoint:  # unset, or "" from `policy.checkpoint=`
        raise InputError(f"policy.kind={cfg.kind} needs policy.checkpoint=<checkpoint directory>")
    if cfg.kind == "vla":
        from mobilemani_vla.policies.vla import VLAEvalPolicy

        return VLAEvalPolicy(cfg.checkpoint, cfg.device, cfg.batch_size)
    if cfg.kind == "lerobot":
        from mobilemani_vla.policies.lerobot import LeRobotEvalPolicy

        return LeRobotEvalPolicy(cfg.checkpoint, cfg.device, cfg.batch_size, cfg.rename)
    from mobilemani_vla.policies.privileged import RandomPolicy, ScriptedEvalPolicy, TeacherEvalPolicy

    if cfg.kind == "teacher":
        return TeacherEvalPolicy(cfg.checkpoint or None, cfg.runs_dir)
    return ScriptedEvalPolicy() if cfg.kind == "scripted" else RandomPolicy()
