"""Every error path of the command line, once: exit 2, one line naming what was expected,
no traceback. ``main`` runs in this process (the same code as the ``unified-manip``
script: argparse, then the command, then the one-line handler); the subprocess tests in
test_cli.py, test_train.py and test_faults.py check the same lines as a user sees them.
Paths covered elsewhere: argparse choices and --set (test_train.py), an owned run or bench
directory and an unloadable checkpoint (test_faults.py), --device (test_recipes.py)."""

from __future__ import annotations

import sys

import pytest
import yaml

from unified_manip.cli import main
from unified_manip.experiments.results import RESULT_COLUMNS
from unified_manip.training import hyperparams

TASK = "UnifiedManip/Arm4Reach-v0"
TRAIN = ["train", "--env", TASK, "--algo", "sac", "--steps", "10", "--no-progress"]
GRID = {
    "name": "g",
    "tasks": [TASK],
    "action_modes": ["ee_delta"],
    "reward_types": ["sparse"],
    "algos": ["sac"],
    "seeds": [0],
    "steps": 10,
}


def one_line_exit_2(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    err = capsys.readouterr().err
    assert exit_.value.code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err.strip()


def write(path, text: str):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def grid(tmp_path, **change) -> str:
    return str(write(tmp_path / "grid.yaml", yaml.safe_dump({**GRID, **change})))


# Each case: (argv builder over tmp_path, expected line). "{t}" is tmp_path.
CASES = {
    "run-dir climbs out": (
        lambda t: TRAIN + ["--run-dir", "runs/../../elsewhere"],
        "unified-manip train: error: --run-dir 'runs/../../elsewhere' climbs out of its directory with '..'; "
        "expected a path without '..' (relative, or absolute)",
    ),
    "run-dir is a file": (
        lambda t: TRAIN + ["--run-dir", str(write(t / "f", "x"))],
        "unified-manip train: error: {t}/f is a file; expected a run directory (choose another --run-dir)",
    ),
    "run-dir is foreign": (
        lambda t: TRAIN + ["--run-dir", str(write(t / "d" / "notes.txt", "x").parent)],
        "unified-manip train: error: {t}/d exists and is not a unified-manip run directory; choose another --run-dir",
    ),
    "run-dir holds another run": (
        lambda t: TRAIN + ["--run-dir", str(write(t / "d" / "config.yaml", yaml.safe_dump({"env": TASK})).parent)],
        "unified-manip train: error: {t}/d holds a different run (it differs in env_kwargs, algo, steps, seed, n_envs, "
        "hyperparameters); choose another --run-dir",
    ),
    "config.yaml not a mapping": (
        lambda t: TRAIN + ["--run-dir", str(write(t / "d" / "config.yaml", "- 1\n").parent)],
        "unified-manip train: error: {t}/d/config.yaml:1: expected a run's settings (written by unified-manip train), got a list",
    ),
    "env kwarg not YAML": (
        lambda t: TRAIN + ["--run-dir", str(t / "r"), "--env-kwarg", "robot=["],
        "unified-manip train: error: argument --env-kwarg: 'robot=[': '[' is not a YAML literal",
    ),
    "env kwarg refused by the task": (
        lambda t: TRAIN + ["--run-dir", str(t / "r"), "--env-kwarg", "robot=Panda"],
        "unified-manip train: error: cannot make UnifiedManip/Arm4Reach-v0 with {'action_mode': 'native', 'reward_type': "
        "'sparse', 'robot': 'Panda'}: Arm4 tasks take no extra options, got ['robot']",
    ),
    "hyperparameter file with a tag": (
        lambda t: TRAIN + ["--run-dir", str(t / "r")] + _baselines(t, "default:\n  learning_rate: !!float 1e-3\n"),
        "unified-manip train: error: {t}/hp/sac.yaml:2: YAML tag '!!float' is not allowed; write plain literals",
    ),
    "hyperparameter file not a mapping": (
        lambda t: TRAIN + ["--run-dir", str(t / "r")] + _baselines(t, "# a list\n- learning_rate: 0.001\n"),
        "unified-manip train: error: {t}/hp/sac.yaml:2: expected a mapping of task IDs with a 'default' entry, got a list",
    ),
    "hyperparameter entry not a mapping": (
        lambda t: (
            TRAIN + ["--run-dir", str(t / "r")] + _baselines(t, "default: {}\nUnifiedManip/Arm4Reach-v0: [1, 2]\n")
        ),
        "unified-manip train: error: {t}/hp/sac.yaml:2: entry 'UnifiedManip/Arm4Reach-v0' must be a mapping of "
        "hyperparameters, got list",
    ),
    "hyperparameter file not YAML": (
        lambda t: TRAIN + ["--run-dir", str(t / "r")] + _baselines(t, "default: {learning_rate: 0.001\n"),
        "unified-manip train: error: {t}/hp/sac.yaml:2: not valid YAML (expected ',' or '}', but got '<stream end>')",
    ),
    "run setting of the wrong type in a hyperparameter file": (
        lambda t: (
            TRAIN
            + ["--run-dir", str(t / "r")]
            + _baselines(t, "default: {policy: MultiInputPolicy}\nUnifiedManip/Arm4Reach-v0: {bc_weight: x}\n")
        ),
        "unified-manip train: error: {t}/hp/sac.yaml: UnifiedManip/Arm4Reach-v0: bc_weight must be a number >= 0, "
        "got 'x'",
    ),
    "run setting out of range in --set": (
        lambda t: TRAIN + ["--run-dir", str(t / "r"), "--set", "n_eval_episodes=0"],
        "unified-manip train: error: --set 'n_eval_episodes=0': n_eval_episodes must be an integer >= 1, got 0",
    ),
    "eval a run whose config.yaml holds a bad setting": (
        lambda t: ["eval", str(_run(t, {"normalize": "yes"}))],
        "unified-manip eval: error: {t}/run/config.yaml: normalize must be true or false, got 'yes'",
    ),
    "eval target missing": (
        lambda t: ["eval", str(t / "nope")],
        "unified-manip eval: error: {t}/nope does not exist; expected a run directory or a model .zip inside one",
    ),
    "eval outside a run": (
        lambda t: ["eval", str(t)],
        "unified-manip eval: error: {t} is not inside a unified-manip run directory (no config.yaml found)",
    ),
    "eval a file that is not a model": (
        lambda t: ["eval", str(_run(t) / "config.yaml")],
        "unified-manip eval: error: {t}/run/config.yaml is not a model; expected a run directory or a model .zip inside one",
    ),
    "eval a run without a model": (
        lambda t: ["eval", str(_run(t))],
        "unified-manip eval: error: {t}/run has no model yet (no best, final or checkpoint model)",
    ),
    "eval video format": (
        lambda t: ["eval", str(t), "--video", "clip.avi"],
        "unified-manip eval: error: unsupported video format '.avi'; expected .mp4 or .gif",
    ),
    "eval episodes": (
        lambda t: ["eval", str(t), "--episodes", "0"],
        "unified-manip eval: error: argument --episodes: expected a positive integer, got '0'",
    ),
    "train randomization preset": (
        lambda t: TRAIN + ["--randomization", "windy"],
        "unified-manip train: error: argument --randomization: unknown randomization preset 'windy'; expected one "
        "of 'none', 'dynamics', 'objects', 'visual', 'all' (joined by '+', each optionally ':extreme' or ':in-range')",
    ),
    "eval test distribution": (
        lambda t: ["eval", str(t), "--test-distribution", "wide"],
        "unified-manip eval: error: argument --test-distribution: invalid choice: 'wide' (choose from 'default', "
        "'in-range', 'extreme')",
    ),
    "eval test distribution of a nominal run without a preset": (
        lambda t: ["eval", str(_run(t)), "--test-distribution", "extreme"],
        "unified-manip eval: error: --test-distribution extreme takes its ranges from a preset, and the run trained "
        "under none; add --randomization PRESET (dynamics, objects, visual or all, joined by '+')",
    ),
    "bench randomizations axis": (
        lambda t: ["bench", grid(t, randomizations=["none", "windy"])],
        "unified-manip bench: error: {t}/grid.yaml: unknown randomization preset 'windy'; expected one of 'none', "
        "'dynamics', 'objects', 'visual', 'all' (joined by '+', each optionally ':extreme' or ':in-range'), or a "
        "list of terms",
    ),
    "bench grid missing": (
        lambda t: ["bench", str(t / "nope.yaml")],
        "unified-manip bench: error: grid file {t}/nope.yaml not found",
    ),
    "bench grid not YAML": (
        lambda t: ["bench", str(write(t / "g.yaml", "tasks: [a\n"))],
        "unified-manip bench: error: {t}/g.yaml:2: not valid YAML (expected ',' or ']', but got '<stream end>')",
    ),
    "bench grid with a tag": (
        lambda t: ["bench", str(write(t / "g.yaml", "name: !!python/name:os.system\n"))],
        "unified-manip bench: error: {t}/g.yaml:1: YAML tag '!!python/name:os.system' is not allowed; "
        "write plain literals",
    ),
    "bench grid not a mapping": (
        lambda t: ["bench", str(write(t / "g.yaml", "[1, 2]\n"))],
        "unified-manip bench: error: {t}/g.yaml:1: expected a mapping with keys tasks, action_modes, "
        "reward_types, algos, seeds, steps, got a list",
    ),
    "bench grid name climbs out": (
        lambda t: ["bench", grid(t, name="../../etc")],
        "unified-manip bench: error: {t}/grid.yaml: name '../../etc' must be a plain directory name "
        "(no '/', '\\', '..' or absolute path): the bench writes to results/<name>",
    ),
    "bench grid name absolute": (
        lambda t: ["bench", grid(t, name="/tmp/x")],
        "unified-manip bench: error: {t}/grid.yaml: name '/tmp/x' must be a plain directory name "
        "(no '/', '\\', '..' or absolute path): the bench writes to results/<name>",
    ),
    "report results missing": (
        lambda t: ["report", str(t / "results.csv")],
        "unified-manip report: error: {t}/results.csv not found; expected a bench's results.csv",
    ),
    "report results not a bench's": (
        lambda t: ["report", str(write(t / "results.csv", "run,task\na,b\n"))],
        "unified-manip report: error: {t}/results.csv: not a bench's results.csv; missing column(s) "
        + ", ".join(RESULT_COLUMNS[2:]),
    ),
    "report malformed row": (
        lambda t: [
            "report",
            str(write(t / "results.csv", ",".join(RESULT_COLUMNS) + "\n" + ",".join(["x"] * 12) + "\n")),
        ],
        "unified-manip report: error: {t}/results.csv:2: malformed row (invalid literal for int() with base 10: 'x')",
    ),
    "report claims with a tag": (
        lambda t: [
            "report",
            str(write(t / "results.csv", ",".join(RESULT_COLUMNS) + "\n")),
            "--claims",
            str(write(t / "claims.yaml", "a: !!python/object:os.system {}\n")),
        ],
        "unified-manip report: error: {t}/claims.yaml:1: YAML tag '!!python/object:os.system' is not allowed; write plain literals",
    ),
    "report claims missing": (
        lambda t: [
            "report",
            str(write(t / "results.csv", ",".join(RESULT_COLUMNS) + "\n")),
            "--claims",
            str(t / "c.yaml"),
        ],
        "unified-manip report: error: {t}/c.yaml: file not found; expected a YAML file holding a mapping of claim labels",
    ),
    "plot figure type": (
        lambda t: ["plot", str(t / "results.csv"), "--out", str(t / "f.jpg")],
        "unified-manip plot: error: argument --out: expected a figure path ending in .png, .svg, .pdf; got '{t}/f.jpg'",
    ),
    "plot results missing": (
        lambda t: ["plot", str(t / "results.csv"), "--out", str(t / "f.png")],
        "unified-manip plot: error: {t}/results.csv not found; expected a bench's results.csv",
    ),
    "plot results empty": (
        lambda t: ["plot", str(write(t / "results.csv", ",".join(RESULT_COLUMNS) + "\n")), "--out", str(t / "f.png")],
        "unified-manip plot: error: {t}/results.csv: no finished runs to plot",
    ),
}


def _baselines(tmp_path, sac_yaml: str) -> list[str]:
    write(tmp_path / "hp" / "sac.yaml", sac_yaml)
    hyperparams.DEFAULT_DIR = tmp_path / "hp"  # restored by the fixture below
    return []


def _run(tmp_path, hyperparameters: dict | None = None):
    """A run directory with its config.yaml (holding ``hyperparameters``) and nothing else yet."""
    write(
        tmp_path / "run" / "config.yaml",
        yaml.safe_dump(
            {
                "env": TASK,
                "algo": "sac",
                "env_kwargs": {"action_mode": "ee_delta", "reward_type": "sparse"},
                "hyperparameters": hyperparameters or {},
            }
        ),
    )
    return tmp_path / "run"


@pytest.fixture
def baselines_dir():
    saved = hyperparams.DEFAULT_DIR
    yield
    hyperparams.DEFAULT_DIR = saved


@pytest.mark.parametrize("case", list(CASES))
def test_cli_error_is_one_line_exit_2(case, tmp_path, capsys, baselines_dir):
    build, expected = CASES[case]
    argv = build(tmp_path)
    assert one_line_exit_2(argv, capsys) == expected.replace("{t}", str(tmp_path))
    assert not (tmp_path / "r").exists()  # a refused train leaves no run directory behind


@pytest.mark.slow
def test_eval_of_a_normalize_run_without_its_statistics(tmp_path, capsys):
    import gymnasium as gym
    from stable_baselines3 import SAC

    run = _run(tmp_path)
    config = yaml.safe_load((run / "config.yaml").read_text())
    config["hyperparameters"] = {"normalize": True}
    (run / "config.yaml").write_text(yaml.safe_dump(config))
    SAC("MultiInputPolicy", gym.make(TASK, action_mode="ee_delta"), learning_starts=10**6).save(run / "final_model.zip")
    assert one_line_exit_2(["eval", str(run), "--episodes", "1"], capsys) == (
        f"unified-manip eval: error: {run}/final_model.zip was trained with normalize: true but {run}/vecnormalize.pkl is missing"
    )


def test_bench_on_a_directory_another_bench_owns(tmp_path, capsys):
    from unified_manip.training.runlock import DirectoryLock

    with DirectoryLock(tmp_path / "out", "bench directory"):
        line = one_line_exit_2(["bench", grid(tmp_path), "--out", str(tmp_path / "out")], capsys)
    assert line.startswith(f"unified-manip bench: error: bench directory {tmp_path / 'out'} is in use by pid ")


@pytest.mark.parametrize(
    "argv",
    [
        ["demo", "--env", "UnifiedManip/Lift-v0", "--out", "never.png", "--no-progress"],
        ["train", "--env", "UnifiedManip/Lift-v0", "--algo", "sac", "--steps", "10", "--no-progress"],
    ],
    ids=["demo", "train"],
)
def test_a_robosuite_id_without_the_extra_names_it(argv, capsys, monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "robosuite", None)  # an install without [robosuite]
    monkeypatch.chdir(tmp_path)
    assert one_line_exit_2(argv, capsys) == (
        f"unified-manip {argv[0]}: error: UnifiedManip/Lift-v0 needs the robosuite extra: "
        'pip install "unified_manip[robosuite]" (missing: robosuite)'
    )
    assert list(tmp_path.iterdir()) == []
