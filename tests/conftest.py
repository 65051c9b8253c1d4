"""Shared fixtures: every registered ID x action mode x reward type."""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import gc
import io
import os
import subprocess
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")
# One torch thread per test process (and per `train` it starts): the suite runs one
# worker per core, and a 2-thread train beside a busy core spins (a 300-step tqc_her
# Lift run: 637 s with 2 threads, 21 s with 1, each beside one 1-thread training run).
os.environ.setdefault("OMP_NUM_THREADS", "1")

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import yaml  # noqa: E402

import unified_manip  # noqa: E402

#: The families with too many IDs to run every per-ID contract on each of them on every
#: run: the contract suites (the fixtures and lists below) take this sample of their IDs
#: (Meta-World's 50 share one backend, observation and action modes; they differ in their
#: goals, which tests/envs/test_metaworld.py checks on every ID in a slow test), and
#: golden_hashes.json keeps every ID's hashes. One Meta-World ID's contracts took about 25 s
#: in its 5 joint and native modes; its two end-effector modes add about 15 s.
SAMPLED_FAMILIES: dict[str, tuple[str, ...]] = {
    "metaworld": ("UnifiedManip/MetaWorldPickPlace-v2",),  # an object carried to a point (the newest version)
}
ALL_IDS = [
    tid
    for tid, spec in unified_manip.TASKS.items()
    if spec.family not in SAMPLED_FAMILIES or tid in SAMPLED_FAMILIES[spec.family]
]
GRIDS = Path(__file__).resolve().parents[1] / "baselines" / "grids"
#: Every committed grid that loads in a fresh clone: all of ``baselines/grids`` but
#: ``studies/``, whose grids read datasets made by ``baselines/grids/studies/make_datasets.sh``.
COMMITTED_GRIDS = sorted(p for p in GRIDS.rglob("*.yaml") if "studies" not in p.relative_to(GRIDS).parts)
#: The families and IDs whose per-mode contracts (test_envs.py's ``case`` and ``pair``
#: fixtures, and the golden rollouts replayed) take a sample of their action modes, for CI
#: time. Every mode of each passed the contracts when it was added, and golden_hashes.json
#: keeps every mode's hashes (``golden.py`` plays them all). An ID's entry wins over its
#: family's.
#: - The kitchen: its 40-substep steps make each mode's cases cost seconds. Its sample is
#:   upstream's controller (native) and one mode on its actuated copy (ee_delta: the rig,
#:   the model copy and mink); its joint modes are the shared controllers other families test.
#: - robosuite's one-arm IDs all put the same Panda on the same controllers, as Fetch's four
#:   IDs put the same Fetch on theirs; they differ in their objects, terms and upstream
#:   env. One ID of each runs every mode (Lift, FetchPickAndPlace: an object carried); the
#:   others run upstream's controller (native) and mink's (ee_delta), which exercise their
#:   own terms and models. The sample halved the golden replays (97 s to 55 s a part).
#:   Most of CI's time had another cause: test processes recompiling their imports (see
#:   the top of .ci/run).
#: - The two-arm robosuite IDs drive two arms' controllers (two IKs in the ee modes): one
#:   mode's contracts took ~17 s on the loaded 2-core machine. The sample holds one mode of
#:   each kind of controller on two arms: ee (PerRig of two IKs) and joint.
#: ``None`` is every mode (an ID's entry over its family's sample).
SAMPLED_MODES: dict[str, tuple[str, ...] | None] = {
    "kitchen": ("native", "ee_delta"),
    "robosuite": ("native", "ee_delta"),
    "UnifiedManip/Lift-v0": None,
    "fetch": ("native", "ee_delta"),
    "UnifiedManip/FetchPickAndPlace-v0": None,
    "UnifiedManip/TwoArmLift-v0": ("ee_delta",),
    "UnifiedManip/TwoArmHandover-v0": ("joint_position",),
}


def _modes(task_id: str) -> tuple[str, ...]:
    spec = unified_manip.TASKS[task_id]
    sample = SAMPLED_MODES[task_id] if task_id in SAMPLED_MODES else SAMPLED_MODES.get(spec.family)
    return tuple(m for m in spec.action_modes if sample is None or m in sample)


ID_MODES = [(tid, mode) for tid in ALL_IDS for mode in _modes(tid)]
ID_MODE_REWARDS = [(tid, mode, r) for tid, mode in ID_MODES for r in unified_manip.REWARD_TYPES]
#: The first registered ID of each family: the integration tests (training, HER) run one
#: task per family; the per-ID contracts (tests/envs) cover every ID.
ONE_ID_PER_FAMILY = list({unified_manip.TASKS[tid].family: tid for tid in reversed(ALL_IDS)}.values())[::-1]
#: One task with an object per family, for the HER tests (a new family must add one:
#: tests/training/test_her.py checks every family is here).
HER_IDS = [
    "UnifiedManip/Arm4PickAndPlace-v0",
    "UnifiedManip/FetchPush-v0",
    "UnifiedManip/HandManipulateBlock-v0",
    "UnifiedManip/Lift-v0",
    "UnifiedManip/AdroitRelocate-v0",
    "UnifiedManip/FrankaKitchen-v0",
    "UnifiedManip/MetaWorldPickPlace-v1",
    "UnifiedManip/ValveTurn-v0",
]


ROOT = Path(__file__).resolve().parents[1]


def cli_in_process(*args: str) -> subprocess.CompletedProcess:
    """``unified-manip ARGS`` run by ``main()`` in this process from the checkout's root, and
    reported as ``subprocess.run`` would: a command in a process of its own first imports
    torch, SB3 and the simulators, about 4.5 s of CPU each time. Tests that signal, kill or
    time a process, or need a fresh interpreter, start one instead."""
    from unified_manip.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(ROOT), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(args))
        except SystemExit as exit_:  # argparse and the one-line errors exit with their code
            code = exit_.code if isinstance(exit_.code, int) else 1
    return subprocess.CompletedProcess(list(args), code or 0, out.getvalue(), err.getvalue())


#: A bench grid that trains in seconds: 2 modes x 2 seeds of 200 steps of Arm4Reach.
TINY_GRID = {
    "name": "tiny",
    "tasks": ["UnifiedManip/Arm4Reach-v0"],
    "action_modes": ["ee_delta", "joint_delta"],
    "reward_types": ["sparse"],
    "algos": ["sac_her"],
    "seeds": [0, 1],
    "steps": 200,
    "eval_freq": 100,
    "n_eval_episodes": 2,
    "overrides": {
        "sac_her": ["learning_starts=50", "batch_size=32", "checkpoint_freq=100", "policy_kwargs.net_arch=[16,16]"]
    },
}


#: Ray's own message when a local node's raylet misses the 30 s it is given to register with
#: the GCS (hard-coded in ray/_private/node.py); a busy machine can miss it.
RAY_NODE_TIMEOUT = "The current node timed out during startup"

#: The marks of a test that starts a local Ray: one such test at a time (xdist group "ray"),
#: and one more try only when Ray's node itself did not start (``RAY_NODE_TIMEOUT``, matched
#: in the failure's message); any other failure fails at once.
LOCAL_RAY = (
    pytest.mark.xdist_group("ray"),
    pytest.mark.flaky(reruns=1, only_rerun=[RAY_NODE_TIMEOUT]),
)


def local_ray(test):
    """Decorate a test that starts a local Ray with :data:`LOCAL_RAY`."""
    for mark in LOCAL_RAY:
        test = mark(test)
    return test


def extra_marks(task_id: str) -> list:
    """The marker of the extra ``task_id``'s family needs (``[pytest.mark.robosuite]``), or
    none: for a parametrised value that is not itself an ID (the collection hook marks those)."""
    extra = unified_manip.TASKS[task_id].extra
    return [getattr(pytest.mark, extra)] if extra else []


def overlay_venv(venv: Path, *requirements: str) -> str:
    """A fresh venv at ``venv`` that sees this venv's packages (through a .pth file) under
    its own ``requirements`` (installed there without their dependencies, e.g.
    ``"minari==0.5.4"``), so a test can run one package's other version beside everything
    else as here; its Python. Its processes import the checkout with ``PYTHONPATH=ROOT``."""
    import sys

    from wheel_install import fresh_venv

    python, site = fresh_venv(venv)
    # addsitedir, not a bare path: the parent's own .pth files (editable installs such as
    # the example family) are read too.
    parents = [p for p in sys.path if p.endswith("site-packages")]
    Path(site, "_parent_deps.pth").write_text("".join(f"import site; site.addsitedir({p!r})\n" for p in parents))
    if requirements:
        pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-q", "--python", python]
        subprocess.run([*pip, "install", "--no-deps", "--no-compile", *requirements], check=True, timeout=600)
    return python


def write_grid(tmp_path: Path, doc: dict, name: str = "grid.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def smoke_mode(task_id: str) -> str:
    """The mode the single-mode smoke tests use: ee_delta where the task has it, else native."""
    modes = unified_manip.TASKS[task_id].action_modes
    return next(m for m in ("ee_delta", "native") if m in modes)


def make(task_id: str, action_mode: str = "native", reward_type: str = "sparse", **kwargs) -> gym.Env:
    return gym.make(task_id, action_mode=action_mode, reward_type=reward_type, **kwargs)


def rollout(env: gym.Env, seed: int, actions: np.ndarray):
    """Reset with ``seed``, play ``actions``; return everything the env produced."""
    obs, info = env.reset(seed=seed)
    out = [(obs, None, None, None, info)]
    for a in actions:
        out.append(env.step(a))
    return out


def random_actions(env: gym.Env, n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(-1.0, 1.0, size=(n,) + env.action_space.shape).astype(np.float32)


DEMO_TASK = "UnifiedManip/Arm4PickAndPlace-v0"
DEMO_MODE = "joint_position"


def demonstrated_model(algo_cls, her: bool, normalize: bool = False):
    """A fresh ``algo_cls`` model on Arm4PickAndPlace-v0 in joint_position (the mode the
    demonstration levers are for), its replay buffer holding two scripted episodes."""
    from stable_baselines3 import HerReplayBuffer
    from stable_baselines3.common.vec_env import VecNormalize

    from unified_manip.training.demonstrations import prefill
    from unified_manip.training.run_envs import make_vec_env

    kwargs = {"action_mode": DEMO_MODE, "reward_type": "sparse"}
    venv = make_vec_env(DEMO_TASK, kwargs, 1, 3, None, "dummy")
    extra = {"replay_buffer_class": HerReplayBuffer} if her else {}
    env = make_vec_env(DEMO_TASK, kwargs, 1, 0, None, "dummy")
    env = VecNormalize(env, norm_reward=False) if normalize else env
    model = algo_cls("MultiInputPolicy", env, buffer_size=2000, learning_starts=10, batch_size=64, seed=0, **extra)
    prefill(model, venv, DEMO_TASK, DEMO_MODE, episodes=2)
    venv.close()
    return model


def resume_to_the_end(request) -> list[str]:
    """Train ``request`` (a run interrupted after its first checkpoint) to the end, check
    that it resumed and finished, and return what it logged."""
    from unified_manip.training.train import train

    logged: list[str] = []
    assert train(request, progress=False, threads=1, log=logged.append)["state"] == "finished"
    assert any("resuming from step" in line for line in logged), logged
    return logged


_GC_EVERY = 20
#: ... and sooner, once a worker's resident memory is over _RSS_LIMIT_MB and has grown by
#: _RSS_GROWTH_MB since the last collection (a robosuite test can add 700 MB of freed heap).
_RSS_LIMIT_MB = 2500
_RSS_GROWTH_MB = 300
_rss_after_gc = 0.0
_tests_since_gc = 0


def interrupt_after_first_checkpoint(run_dir, call) -> None:
    """Run ``call()`` (a ``train`` of ``run_dir`` in this process) and Ctrl-C it once its
    first checkpoint is published: ``train`` checkpoints and raises KeyboardInterrupt."""
    import signal
    import threading

    from unified_manip.training import checkpoints

    def interrupt():
        while not checkpoints.published(run_dir):
            threading.Event().wait(0.2)
        os.kill(os.getpid(), signal.SIGINT)

    watcher = threading.Thread(target=interrupt, daemon=True)
    watcher.start()
    with pytest.raises(KeyboardInterrupt):
        call()
    watcher.join()


#: glibc's ``malloc_trim`` (None where the C library has none).
_MALLOC_TRIM = getattr(ctypes.CDLL(ctypes.util.find_library("c")), "malloc_trim", None)


@pytest.fixture(autouse=True)
def _collect_cycles():
    """Every ``_GC_EVERY`` tests, run a full garbage collection and hand malloc's free
    memory back to the system.

    robosuite's envs hold reference cycles, and the MuJoCo memory they keep is invisible
    to Python's GC thresholds: without the collection an xdist worker grew to 9-13 GB and
    was OOM-killed (the golden rollouts alone: 3.7 GB peak without a collection per env,
    0.9 GB with one). And glibc keeps freed memory for reuse: MuJoCo models are tens of MB,
    above malloc's mmap threshold only until the first is freed (the threshold then rises
    to 32 MB), so the later ones land in the heap and leave it fragmented. A worker's
    resident memory rose to 4.6 GB over the robosuite cases, 2.6 GB of it free memory
    that one ``malloc_trim`` returned (``UM_TEST_RSS`` logs); with the trim every 20 tests
    alone, one robosuite test still took a worker from 3.3 to 4.05 GB."""
    global _tests_since_gc, _rss_after_gc
    yield
    _tests_since_gc += 1
    rss = _rss_mb()
    if _tests_since_gc >= _GC_EVERY or rss > max(_RSS_LIMIT_MB, _rss_after_gc + _RSS_GROWTH_MB):
        _tests_since_gc = 0
        gc.collect()
        if _MALLOC_TRIM is not None:
            _MALLOC_TRIM(0)
        _rss_after_gc = _rss_mb()


def _rss_mb() -> float:
    """This process's resident memory, MB (from ``/proc/self/statm``: a few microseconds)."""
    return int(Path("/proc/self/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


#: ``UM_TEST_RSS=FILE``: after each test, append "test VmRSS VmHWM" (MB) to FILE.<worker>,
#: to find which tests hold memory (the README's test-memory figures come from it).
_RSS_LOG = os.environ.get("UM_TEST_RSS")


def pytest_runtest_logfinish(nodeid, location):
    if _RSS_LOG:
        status = Path("/proc/self/status").read_text()
        mb = [int(status.split(f"{k}:")[1].split()[0]) // 1024 for k in ("VmRSS", "VmHWM")]
        with open(f"{_RSS_LOG}.{os.environ.get('PYTEST_XDIST_WORKER', 'main')}", "a") as log:
            log.write(f"{nodeid} {mb[0]} {mb[1]}\n")


#: The family whose parametrised cases stay in the fast subset (``pytest -m "not slow"``).
FAST_FAMILY = "arm4"


def _spec(value) -> unified_manip.TaskSpec | None:
    """The task a parametrised value names (or starts with), if any."""
    if isinstance(value, (tuple, list)) and value:
        value = value[0]
    return unified_manip.TASKS.get(value) if isinstance(value, str) else None


def pytest_collection_modifyitems(items):
    """The fast subset runs every parametrised contract on the arm family (MuJoCo only,
    milliseconds a step); the same cases on Fetch, the Shadow Hand and robosuite carry
    ``slow``. CI runs them all.

    A case of a task whose family needs an extra (``TaskSpec.extra``: robosuite's) carries
    that extra's marker (``robosuite``), as do the tests marked so in their code, so that
    an install without it deselects them by name: ``-m "not robosuite"``.

    The tests marked ``slow`` in their code (whole training runs, benches, subprocesses:
    tens of seconds each) then move ahead of the others, in their own order. pytest-xdist's
    ``loadgroup`` hands out xdist groups first, largest first, then single tests in this
    order, so the long ones start early and short ones fill the end of both workers."""
    explicit = {id(item) for item in items if item.get_closest_marker("slow") is not None}
    for item in items:
        callspec = getattr(item, "callspec", None)
        specs = [s for s in map(_spec, callspec.params.values()) if s is not None] if callspec is not None else []
        if any(s.family != FAST_FAMILY for s in specs):
            item.add_marker(pytest.mark.slow)
        for extra in sorted({s.extra for s in specs if s.extra is not None}):
            item.add_marker(getattr(pytest.mark, extra))
    items.sort(key=lambda item: id(item) not in explicit)


@pytest.fixture(params=ID_MODE_REWARDS, ids=lambda p: "-".join(p).replace("UnifiedManip/", ""))
def id_mode_reward(request):
    return request.param


@pytest.fixture(params=ID_MODES, ids=lambda p: "-".join(p).replace("UnifiedManip/", ""))
def id_mode(request):
    return request.param
