"""Checkpoint size and write time: SB3's whole-buffer pickle against the trimmed checkpoint.

    python -m benchmarks.checkpoint_size --steps 10000 --buffer-size 1000000

Builds the ``sac_her`` baseline of a task (its hyperparameters, with ``buffer_size`` as
given), plays ``--steps`` env steps without learning (``learning_starts`` past them, so
only the buffer fills), then times, ``--repeats`` times each (medians):

- *before*: what a checkpoint was until issue 12, ``model.save`` plus SB3's
  ``save_replay_buffer`` (the whole preallocated buffer pickled) plus the observation
  statistics;
- *after*: :func:`unified_manip.training.checkpoints.write` (trimmed buffer, SHA-256 digests,
  fsync, manifest);
- loading each buffer back (SB3's ``load_replay_buffer`` against
  :func:`unified_manip.training.checkpoints.restore_replay_buffer` into a fresh full-capacity buffer).
"""

from __future__ import annotations

import argparse
import json
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from benchmarks.parser import ToolParser


def _model(task: str, buffer_size: int, steps: int):
    from unified_manip.training.algorithms import get_algo
    from unified_manip.training.hyperparams import resolve_run
    from unified_manip.training.run_envs import make_vec_env
    from unified_manip.training.run_envs import model_kwargs as _model_kwargs
    from unified_manip.training.run_envs import normalized as _normalized

    resolved = resolve_run("sac_her", task, (f"buffer_size={buffer_size}", f"learning_starts={steps * 2}"))
    run, kwargs = resolved.run, resolved.algo_kwargs
    env = _normalized(
        make_vec_env(task, {"action_mode": "ee_delta", "reward_type": "sparse"}, 1, 0, None),
        run,
        None,
        True,
        gamma=float(kwargs.get("gamma", 0.99)),
    )
    model = get_algo("sac_her").cls()(
        env=env, seed=0, device="cpu", verbose=0, **_model_kwargs("sac_her", kwargs, run, env)
    )
    model.learn(steps)
    return model


def _size(path: Path) -> int:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())


def _timed(fn, repeats: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def measure(task: str, buffer_size: int, steps: int, repeats: int) -> dict:
    from unified_manip.training import checkpoints

    model = _model(task, buffer_size, steps)
    work = Path(tempfile.mkdtemp(prefix="ckpt_size_"))
    try:

        def before() -> Path:
            d = work / "before"
            shutil.rmtree(d, ignore_errors=True)
            d.mkdir()
            model.save(d / "model.zip")
            model.save_replay_buffer(d / "replay_buffer.pkl")
            model.get_vec_normalize_env().save(str(d / "vecnormalize.pkl"))
            return d

        def after() -> Path:
            shutil.rmtree(work / "after", ignore_errors=True)
            return checkpoints.write(model, work / "after", off_policy=True).directory

        t_before, d_before = _timed(before, repeats)
        t_after, d_after = _timed(after, repeats)
        ckpt = checkpoints.newest(work / "after")
        fresh = _model(task, buffer_size, 1)  # a full-capacity buffer, as a resumed run builds it
        t_load_before, _ = _timed(lambda: fresh.load_replay_buffer(d_before / "replay_buffer.pkl"), repeats)
        fresh = _model(task, buffer_size, 1)
        t_load_after, _ = _timed(lambda: checkpoints.restore_replay_buffer(fresh, ckpt), repeats)
        return {
            "task": task,
            "buffer_size": buffer_size,
            "steps": steps,
            "repeats": repeats,
            "before": {
                "checkpoint_bytes": _size(d_before),
                "buffer_bytes": (d_before / "replay_buffer.pkl").stat().st_size,
                "write_s": t_before,
                "buffer_load_s": t_load_before,
            },
            "after": {
                "checkpoint_bytes": _size(d_after),
                "buffer_bytes": ckpt.path(checkpoints.REPLAY_BUFFER).stat().st_size,
                "write_s": t_after,
                "buffer_load_s": t_load_after,
            },
        }
    finally:
        shutil.rmtree(work, ignore_errors=True)


def table(r: dict) -> str:
    b, a = r["before"], r["after"]
    rows = [
        ("checkpoint size (MB)", b["checkpoint_bytes"] / 1e6, a["checkpoint_bytes"] / 1e6),
        ("of which replay buffer (MB)", b["buffer_bytes"] / 1e6, a["buffer_bytes"] / 1e6),
        ("checkpoint write time (s)", b["write_s"], a["write_s"]),
        ("replay buffer load time (s)", b["buffer_load_s"], a["buffer_load_s"]),
    ]
    lines = [
        f"{r['task']}, sac_her, buffer_size {r['buffer_size']:,}, after {r['steps']:,} steps "
        f"(median of {r['repeats']})",
        "",
        "| | before (whole buffer) | after (trimmed) | after / before |",
        "|---|---:|---:|---:|",
    ]
    lines += [f"| {name} | {x:,.3f} | {y:,.3f} | {y / x:.3f} |" for name, x, y in rows]
    return "\n".join(lines)


def _positive(value: str) -> int:
    if not value.isdigit() or int(value) <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value!r}")
    return int(value)


def main(argv: list[str] | None = None) -> int:
    parser = ToolParser("benchmarks.checkpoint_size", __doc__)
    from unified_manip.envs.registry import TASKS

    ids = [t for t, spec in TASKS.items() if "ee_delta" in spec.action_modes]
    parser.add_argument(
        "--task",
        default="UnifiedManip/Arm4PickAndPlace-v0",
        choices=ids,
        metavar="ID",
        help="a registered ID with ee_delta",
    )
    parser.add_argument("--buffer-size", type=_positive, default=1_000_000)
    parser.add_argument("--steps", type=_positive, default=10_000)
    parser.add_argument("--repeats", type=_positive, default=3)
    parser.add_argument("--json", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    result = measure(args.task, args.buffer_size, args.steps, args.repeats)
    print(table(result))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
