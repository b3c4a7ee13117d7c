"""Build the evaluation policy a PolicyCfg names; model stacks are imported only when used."""

from __future__ import annotations

from mobilemani_rl.utils.errors import InputError, check_choice
from mobilemani_vla.eval.config import PolicyCfg
from mobilemani_vla.eval.policies.base import EvalPolicy

KINDS = ("vla", "lerobot", "teacher", "scripted", "random")
# The kinds that read each setting: given to another kind, it would be ignored without a word.
READ_BY = {
    "checkpoint": ("vla", "lerobot", "teacher"),
    "runs_dir": ("teacher",),
    "device": ("vla", "lerobot"),
    "batch_size": ("vla", "lerobot"),
    "rename": ("lerobot",),
    "null_image": ("vla",),
}


def build_policy(cfg: PolicyCfg) -> EvalPolicy:
    check_choice(cfg.kind, KINDS, "policy kind")
    if cfg.kind in ("vla", "lerobot") and not cfg.checkpoint:  # unset, or "" from `policy.checkpoint=`
        raise InputError(f"policy.kind={cfg.kind} needs policy.checkpoint=<checkpoint directory>")
    defaults = PolicyCfg()
    unread = [
        f"policy.{key}={value}"
        for key, kinds in READ_BY.items()
        if cfg.kind not in kinds and (value := getattr(cfg, key)) and value != getattr(defaults, key)
    ]
    if unread:
        raise InputError(f"policy.kind={cfg.kind} does not read {', '.join(unread)}; leave it out")
    if cfg.kind == "vla":
        from mobilemani_vla.eval.policies.vla import VLAEvalPolicy

        return VLAEvalPolicy(cfg.checkpoint, cfg.device, cfg.batch_size, cfg.null_image)
    if cfg.kind == "lerobot":
        from mobilemani_vla.eval.policies.lerobot import LeRobotEvalPolicy

        return LeRobotEvalPolicy(cfg.checkpoint, cfg.device, cfg.batch_size, cfg.rename)
    from mobilemani_vla.eval.policies.privileged import RandomPolicy, ScriptedEvalPolicy, TeacherEvalPolicy

    if cfg.kind == "teacher":
        return TeacherEvalPolicy(cfg.checkpoint or None, cfg.runs_dir)
    return ScriptedEvalPolicy() if cfg.kind == "scripted" else RandomPolicy()
