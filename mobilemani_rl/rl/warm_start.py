"""Warm start of a PPO teacher from the scripted policy (a deviation from the reference: on in the
cpu preset, off in the paper preset).

The reference trains every teacher from scratch on ~65M samples. A 2-core machine collects ~7M in an hour,
enough for reaching and opening but too few for PPO to discover a grasp that lifts an object (it learns to
hover beside it). Here the actor first clones the scripted policy (mean-squared error on its actions) from
episodes in which noise perturbs the executed actions but not the labels (DART, Laskey et al. 2017): plain
cloning drifts into states that clean scripted episodes never visit and stalls there
(docs/results/teachers.md). The critic is fitted to the discounted returns of the task reward in those
episodes. PPO then trains on the task reward alone, as the reference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch
from tensordict import TensorDict
from tqdm import tqdm

from mobilemani_rl.envs.actions import dart_perturbed
from mobilemani_rl.envs.batched import BatchedEnv
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult
from mobilemani_rl.envs.multi_object import MultiObjectEnv
from mobilemani_rl.envs.rollout import run_first_episodes
from mobilemani_rl.rl.config import WarmStartCfg
from mobilemani_rl.rl.runner import torch_threads
from mobilemani_rl.scripted.policy import ScriptedPolicy


@dataclass
class Demonstrations:
    obs: np.ndarray  # (steps, obs_dim)
    actions: np.ndarray  # (steps, num_actions) the scripted policy's noise-free actions there
    returns: np.ndarray  # (steps,) discounted return from each step to its episode's end
    episodes: int
    successes: int


class _LabellingPolicy:
    """Executes the scripted policy's actions plus noise and stores each step's observation, the scripted
    (noise-free) action and the reward; counts each control step on the progress bar."""

    def __init__(self, env: MobileManiEnv, noise: float, seed: int, bar: tqdm) -> None:
        self.env, self.noise, self.bar = env, noise, bar
        self.rng = np.random.default_rng(seed)
        self.scripted = ScriptedPolicy(env)
        self.obs: list[np.ndarray] = []
        self.labels: list[np.ndarray] = []
        self.rewards: list[np.ndarray] = []

    def __call__(self) -> np.ndarray:
        self.obs.append(self.env.obs.copy())
        self.labels.append(self.scripted())
        return dart_perturbed(self.labels[-1], self.noise, self.rng)

    def on_step(self, result: StepResult) -> None:
        self.rewards.append(result.reward)
        self.bar.update()


def discounted_returns(rewards: np.ndarray, gamma: float) -> np.ndarray:
    """(steps, envs) return-to-go of rewards that are already zero past each episode's end."""
    returns = np.zeros_like(rewards)
    running = np.zeros(rewards.shape[1])
    for t in range(rewards.shape[0] - 1, -1, -1):
        running = rewards[t] + gamma * running
        returns[t] = running
    return returns


def record_batch(env: MobileManiEnv, noise: float, seed: int, gamma: float, bar: tqdm) -> Demonstrations:
    """One perturbed scripted episode in every env of the batch."""
    policy = _LabellingPolicy(env, noise, seed, bar)
    stats = run_first_episodes(env, policy, seed, on_step=policy.on_step)
    in_episode = np.arange(len(policy.obs))[:, None] < stats.length[None, :]  # (steps, envs)
    returns = discounted_returns(np.where(in_episode, np.stack(policy.rewards), 0.0), gamma)
    return Demonstrations(
        np.stack(policy.obs)[in_episode],
        np.stack(policy.labels)[in_episode],
        returns[in_episode],
        episodes=env.num_envs,
        successes=int(stats.success.sum()),
    )


def collect(env: BatchedEnv, episodes: int, noise: float, seed: int, gamma: float) -> Demonstrations:
    """At least `episodes` labelled episodes of every object (a multi-object env holds one env per object)."""
    batches = [
        (part, seed + i)
        for part in (env.envs if isinstance(env, MultiObjectEnv) else [env])
        for i in range(math.ceil(episodes / part.num_envs))
    ]
    length = env.max_episode_length
    # Minutes on a CPU: a bar over the batches' control steps gives the total and an ETA.
    with tqdm(
        total=len(batches) * length,
        unit="step",
        dynamic_ncols=True,
        desc=f"warm start: {sum(part.num_envs for part, _ in batches)} scripted episodes",
    ) as bar:
        parts = []
        for k, (part, batch_seed) in enumerate(batches):
            parts.append(record_batch(part, noise, batch_seed, gamma, bar))
            bar.n = (k + 1) * length  # a batch whose episodes all ended early skips its remaining steps
            bar.refresh()
    return Demonstrations(
        *(np.concatenate([getattr(p, f) for p in parts]) for f in ("obs", "actions", "returns")),
        episodes=sum(p.episodes for p in parts),
        successes=sum(p.successes for p in parts),
    )


def fit(
    model: torch.nn.Module, inputs: np.ndarray, targets: np.ndarray, cfg: WarmStartCfg, name: str
) -> list[float]:
    """Mean-squared-error regression of the model's (deterministic) output; returns the loss of each epoch."""
    device = next(model.parameters()).device
    x = torch.from_numpy(inputs).float().to(device)
    y = torch.from_numpy(targets).float().reshape(len(targets), -1).to(device)
    optimizer = torch.optim.Adam(model.parameters(), lr=cfg.learning_rate)
    generator = torch.Generator().manual_seed(cfg.seed)
    losses = []
    with tqdm(
        total=cfg.epochs, desc=f"warm start: fitting the {name}", unit="epoch", dynamic_ncols=True
    ) as bar:
        for _ in range(cfg.epochs):
            total = 0.0
            for batch in torch.randperm(len(x), generator=generator).split(cfg.mini_batch_size):
                prediction = model(TensorDict({"policy": x[batch]}, batch_size=[len(batch)]))
                loss = torch.nn.functional.mse_loss(prediction, y[batch])
                optimizer.zero_grad()
                loss.backward()
                optimizer.step()
                total += loss.item() * len(batch)
            losses.append(total / len(x))
            bar.set_postfix(loss=f"{losses[-1]:.4g}", refresh=False)
            bar.update()
    return losses


def warm_start(
    actor: torch.nn.Module,
    critic: torch.nn.Module,
    env: BatchedEnv,
    cfg: WarmStartCfg,
    gamma: float,
    fit_threads: int = 0,
) -> dict:
    """Clone the scripted policy into the actor, fit the critic to its returns and set the action noise
    (the fitting with `fit_threads` torch threads: MuJoCo is idle then).

    The env is left reset, so that training starts from fresh episodes.
    """
    demos = collect(env, cfg.episodes, cfg.action_noise, cfg.seed, gamma)
    device = next(actor.parameters()).device
    obs = TensorDict(
        {"policy": torch.from_numpy(demos.obs).float()}, batch_size=[len(demos.obs)], device=device
    )
    for model in (actor, critic):  # the normalisers start from the scripted states, as PPO's policy would see
        model.train()
        model.update_normalization(obs)
    with torch_threads(fit_threads):
        actor_losses = fit(actor, demos.obs, demos.actions, cfg, "actor")
        critic_losses = fit(critic, demos.obs, demos.returns, cfg, "critic")
    with torch.no_grad():
        actor.distribution.std_param.fill_(cfg.noise_std)
    env.reset(seed=cfg.seed)
    return {
        "episodes": demos.episodes,
        "scripted_success": demos.successes / demos.episodes,
        "steps": len(demos.obs),
        "actor_loss": [actor_losses[0], actor_losses[-1]],
        "critic_loss": [critic_losses[0], critic_losses[-1]],
    }
