"""The training callbacks: success rate, checkpoints, progress, best-model statistics,
and reward terms. :func:`make_callbacks` puts a run's list together.
"""

from __future__ import annotations

import os
from collections import deque
from pathlib import Path
from typing import Callable, Mapping

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback, CallbackList, EvalCallback

from unified_manip.training import checkpoints
from unified_manip.training.rundir import write_status
from unified_manip.training.settings import RunConfig


class SuccessRate(BaseCallback):
    """SB3 logs ``rollout/success_rate`` only for off-policy algorithms; log it for all."""

    def __init__(self, off_policy: bool):
        super().__init__()
        self.off_policy = off_policy

    def _on_rollout_end(self) -> None:
        if not self.off_policy and len(self.model.ep_success_buffer) > 0:
            self.logger.record("rollout/success_rate", float(np.mean(self.model.ep_success_buffer)))

    def _on_step(self) -> bool:
        return True

    def _on_training_end(self) -> None:
        # Off-policy SB3 dumps logs only every log_interval episodes; make sure the
        # last success rate of a run reaches TensorBoard whatever the algorithm.
        if len(self.model.ep_success_buffer) > 0:
            self.logger.record("rollout/success_rate", float(np.mean(self.model.ep_success_buffer)))
            self.logger.dump(self.num_timesteps)


class StopOnSignal(BaseCallback):
    """Turns Ctrl-C (and SIGTERM) into a stop where the checkpoint written on the way out
    is whole: at the start of the next rollout, after the last update.

    SB3 counts an env step before its callbacks see it and stores the transition after
    them, so an interrupt raised wherever the signal lands could checkpoint a step count
    one transition ahead of the replay buffer. :meth:`request` is the signal handler: the
    first signal sets a flag that :meth:`_on_rollout_start` turns into
    ``KeyboardInterrupt`` (with :attr:`whole` set); a second one raises at once, and the
    run then resumes from its last periodic checkpoint.
    """

    def __init__(self):
        super().__init__()
        self.requested = False
        self.whole = False

    def request(self, signum, frame) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True
        os.write(
            2,
            b"stopping at the next rollout boundary, after any evaluation in progress, to write a checkpoint"
            b" (interrupt again to stop at once, without one)\n",
        )

    def _on_rollout_start(self) -> None:
        if self.requested:
            self.whole = True
            raise KeyboardInterrupt

    def _on_step(self) -> bool:
        return True


class Checkpoint(BaseCallback):
    """Saves a resumable checkpoint of ``run_dir`` every ``freq`` env steps (atomically).

    It saves at the end of a rollout, where the replay buffer holds every transition
    counted in ``num_timesteps`` (during ``on_step`` the last one is not stored yet).
    After each checkpoint the status records the step and ``elapsed()``, the run's wall
    time so far, so a run killed outright (kill -9, the end of a session) resumes with
    the time it had spent up to its checkpoint rather than from 0.
    """

    def __init__(self, freq: int, run_dir: Path, off_policy: bool, elapsed: Callable[[], float]):
        super().__init__()
        self.freq = max(int(freq), 1)
        self.run_dir = run_dir
        self.off_policy = off_policy
        self.elapsed = elapsed
        self.last = 0

    def _on_training_start(self) -> None:
        self.last = self.num_timesteps

    def _on_step(self) -> bool:
        return True

    def _on_rollout_end(self) -> None:
        # At the first rollout end past each multiple of freq: a resumed run keeps the
        # schedule of an uninterrupted one (10k, 20k, ...), not one shifted by its resume step.
        if self.num_timesteps // self.freq > self.last // self.freq:
            checkpoints.write(self.model, self.run_dir, self.off_policy)
            write_status(
                self.run_dir, state="running", num_timesteps=int(self.num_timesteps), wall_time_s=self.elapsed()
            )
            self.last = self.num_timesteps


class Progress(BaseCallback):
    """A bar with steps, steps/s, ETA and the latest success rate (hidden unless ``show``)."""

    def __init__(self, total: int, show: bool):
        super().__init__()
        self.total = total
        self.show = show

    def _on_training_start(self) -> None:
        from tqdm import tqdm

        self.bar = tqdm(
            total=self.total, initial=self.num_timesteps, unit="step", dynamic_ncols=True, disable=not self.show
        )

    def _on_step(self) -> bool:
        self.bar.update(self.num_timesteps - self.bar.n)
        buf = self.model.ep_success_buffer
        if len(buf) and self.n_calls % 50 == 0:
            self.bar.set_postfix(success=f"{np.mean(buf):.2f}", refresh=False)
        return True

    def _on_training_end(self) -> None:
        self.bar.close()


class SaveBestStats(BaseCallback):
    """Keeps ``best/vecnormalize.pkl`` in step with ``best/best_model.zip``."""

    def __init__(self, run_dir: Path):
        super().__init__()
        self.run_dir = run_dir

    def _on_step(self) -> bool:
        if self.model.get_vec_normalize_env() is not None:
            from unified_manip.training.run_envs import save_stats

            (self.run_dir / "best").mkdir(parents=True, exist_ok=True)
            save_stats(self.model, self.run_dir / "best" / "vecnormalize.pkl")
        return True


class RewardTerms(BaseCallback):
    """Logs each reward term's episode total, averaged over the last ``window`` episodes:
    scaled as ``reward_terms/<name>`` (they add up to ``rollout/ep_rew_mean``) and before
    its scale as ``reward_terms_raw/<name>`` (MuJoCo Playground's raw metrics), so an
    agent that farms one term is visible.

    The scaled terms are the step's ``info["reward_terms"]``; a raw term is the scaled
    one divided by its scale (``scales``, name to scale). A term whose scale is 0 has no
    raw value to recover and is logged scaled only. The env's info is left unchanged.
    """

    def __init__(self, scales: Mapping[str, float], window: int = 100):
        super().__init__()
        self.scales = dict(scales)
        self.window = window

    def _on_training_start(self) -> None:
        n = self.training_env.num_envs
        self.sums: list[dict[str, float]] = [{} for _ in range(n)]
        self.episodes: deque[dict[str, float]] = deque(maxlen=self.window)

    def _on_step(self) -> bool:
        infos, dones = self.locals.get("infos"), self.locals.get("dones")
        if infos is None or dones is None:
            return True
        ended = False
        for i, (info, done) in enumerate(zip(infos, dones)):
            terms = info.get("reward_terms")
            if isinstance(terms, Mapping):
                sums = self.sums[i]
                for name, value in terms.items():
                    sums[name] = sums.get(name, 0.0) + float(value)
            if done:
                self.episodes.append(self.sums[i])
                self.sums[i] = {}
                ended = True
        if ended:
            self._record()
        return True

    def _record(self) -> None:
        names = {name for episode in self.episodes for name in episode}
        for name in sorted(names):
            total = float(np.mean([episode.get(name, 0.0) for episode in self.episodes]))
            self.logger.record(f"reward_terms/{name}", total)
            scale = self.scales.get(name, 0.0)
            if scale != 0.0:
                self.logger.record(f"reward_terms_raw/{name}", total / scale)


def resume_evaluations(evaluation: EvalCallback, path: Path, upto: int) -> None:
    """Give a resumed run's EvalCallback the evaluations made up to its checkpoint.

    EvalCallback starts with empty lists and rewrites ``evaluations.npz`` from them: a
    resumed run would lose its earlier curve, and its first evaluation would replace the
    best model whatever it scored. Evaluations after ``upto`` (made past the checkpoint
    by the attempt that was cut short) are dropped; they are made again.
    """
    try:
        with np.load(path) as data:
            keep = data["timesteps"] <= upto
            evaluation.evaluations_timesteps = data["timesteps"][keep].tolist()
            evaluation.evaluations_results = data["results"][keep].tolist()
            evaluation.evaluations_length = data["ep_lengths"][keep].tolist()
            if "successes" in data:
                evaluation.evaluations_successes = data["successes"][keep].tolist()
    except (OSError, ValueError, KeyError):  # none yet, or cut off while written: start afresh
        return
    if evaluation.evaluations_results:
        evaluation.best_mean_reward = float(max(np.mean(r) for r in evaluation.evaluations_results))


def make_callbacks(
    total: int,
    run_dir: Path,
    run: RunConfig,
    eval_env,
    off_policy: bool,
    progress: bool,
    scales: Mapping[str, float],
    elapsed: Callable[[], float],
    resumed_at: int = 0,
    stop: StopOnSignal | None = None,
) -> CallbackList:
    """The callbacks of a run that trains to ``total`` env steps; ``elapsed()`` is the
    run's wall time so far (all segments), recorded at each checkpoint.

    ``run`` gives the evaluation and checkpoint frequencies and the number of *training*
    envs (``n_envs``): EvalCallback counts calls of the training env's step, each ``n_envs``
    env steps, so ``eval_freq`` (env steps) is divided by it. ``scales`` are the reward terms' scales (:class:`RewardTerms`);
    ``stop`` is the run's :class:`StopOnSignal`, if it handles signals.
    """
    evaluation = EvalCallback(
        eval_env,
        callback_on_new_best=SaveBestStats(run_dir),
        eval_freq=max(run.eval_freq // run.n_envs, 1),
        n_eval_episodes=run.n_eval_episodes,
        log_path=str(run_dir / "eval"),
        best_model_save_path=str(run_dir / "best"),
        deterministic=True,
        verbose=0,
    )
    if resumed_at:
        resume_evaluations(evaluation, run_dir / "eval" / "evaluations.npz", resumed_at)
        # EvalCallback evaluates when its call count is a multiple of eval_freq; counting
        # on from the resume step keeps the evaluation points of an uninterrupted run, the
        # last one at the budget.
        evaluation.n_calls = resumed_at // run.n_envs
    return CallbackList(
        [
            *([stop] if stop is not None else []),
            RewardTerms(scales),
            SuccessRate(off_policy),
            Checkpoint(run.checkpoint_freq, run_dir, off_policy, elapsed),
            evaluation,
            Progress(total, progress),
        ]
    )
