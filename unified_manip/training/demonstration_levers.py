"""The demonstration levers of a new run, in the order ``train`` applies them: fill the
replay buffer (live scripted episodes or a dataset) and behaviour-clone the actor
(:func:`demonstrate`), keep a cloning loss on every actor update (:func:`keep_cloning`),
and take offline steps on the demonstrations alone (:func:`learn_offline_on_demonstrations`).
Each records what it did in the run's ``demonstrations.json``.
"""

from __future__ import annotations

import json

from unified_manip.training.request import TrainError, TrainRequest
from unified_manip.training.run_envs import make_vec_env
from unified_manip.training.rundir import write_atomic
from unified_manip.training.settings import CloningLossConfig, RunConfig, demonstration_settings


def demonstrate(model, req: TrainRequest, run: RunConfig, log) -> None:
    """Fill the new model's replay buffer with the scripted policy's ``demonstrations``
    episodes, played in envs of their own (see :mod:`unified_manip.training.demonstrations`), then
    behaviour-clone its actor on them for ``bc_steps`` (0: none; :mod:`unified_manip.training.pretrain`),
    after seeding a normalising run's statistics from them where it clones or learns offline.
    ``demonstrations.json`` records what was stored and learned beside every demonstration
    setting under its own name (:func:`~unified_manip.training.settings.demonstration_settings`);
    results.csv carries it."""
    from unified_manip.training.demonstrations import SEED_OFFSET, prefill
    from unified_manip.training.pretrain import behaviour_clone, seed_statistics

    source = run.demos.demonstrations
    if isinstance(source, str):  # a dataset's episodes (unified_manip.training.dataset_demonstrations)
        from unified_manip.training.dataset_demonstrations import prefill as prefill_from_dataset

        done = prefill_from_dataset(model, source, req.env, req.env_config())
    else:
        # DummyVecEnv: the scripted policy reads each env's own rig in modes other than ee_delta.
        venv = make_vec_env(req.env, req.env_config(), run.n_envs, req.seed + SEED_OFFSET, None, "dummy")
        try:
            done = prefill(model, venv, req.env, req.action_mode, source)
        finally:
            venv.close()
    log(
        f"{req.directory}: {done['episodes']} demonstration episodes ({done['transitions']} transitions, "
        f"{done['success']:.2f} success) in the replay buffer"
        + (f" from {done['dataset']}" if "dataset" in done else "")
    )
    done.update(demonstration_settings(run))
    bc_steps = run.demos.bc_steps
    if bc_steps or run.offline.offline_steps:
        seed_statistics(model)
    if bc_steps:
        cloned = behaviour_clone(model, bc_steps)
        done["behaviour_cloning"] = {k: v for k, v in cloned.items() if k != "steps"}  # bc_steps says how many
        log(
            f"{req.directory}: behaviour cloning, {bc_steps} actor steps on the demonstrations "
            f"(loss {cloned['loss_first']:.3f} -> {cloned['loss_last']:.3f})"
        )
    write_atomic(req.directory / "demonstrations.json", json.dumps(done, indent=2) + "\n")


def learn_offline_on_demonstrations(model, req: TrainRequest, steps: int, log, progress: bool) -> None:
    """Take ``steps`` of the algorithm's own updates on the demonstrations alone
    (:mod:`unified_manip.training.offline`) and add what they learned to ``demonstrations.json``."""
    from unified_manip.training.offline import learn_offline

    path = req.directory / "demonstrations.json"
    done = json.loads(path.read_text())
    learned = learn_offline(model, steps, progress)
    done["offline"] = {k: v for k, v in learned.items() if k != "steps"}  # offline_steps says how many
    first, last = learned["first"].get("train/critic_loss"), learned["last"].get("train/critic_loss")
    log(
        f"{req.directory}: {steps} offline steps of {req.algo} on the demonstrations alone"
        + (f" (critic loss {first:.3f} -> {last:.3f})" if first is not None and last is not None else "")
    )
    write_atomic(path, json.dumps(done, indent=2) + "\n")


def keep_cloning(model, req: TrainRequest, loss: CloningLossConfig) -> None:
    """Add the cloning loss ``loss`` on the recorded demonstrations to every actor update
    from here on (:mod:`unified_manip.training.cloning_loss`; a resumed run adds it again)."""
    from unified_manip.training.cloning_loss import CloningLossError, attach

    done = json.loads((req.directory / "demonstrations.json").read_text())
    try:
        attach(model, done["transitions"], req.steps, loss.bc_weight, loss.bc_q_filter, loss.bc_sampled)
    except CloningLossError as err:
        raise TrainError(f"{req.directory}: {err}") from None
