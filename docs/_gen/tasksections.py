"""The generated sections of a task page: the action space per mode (from live envs), the
reward designs (from the env's reward specs), the episode end, the ``gym.make`` keywords
(from :class:`~unified_manip.envs.config.EnvConfig`) and the benchmark rows (from the
committed ``results/benchmark*/results.csv``)."""

from __future__ import annotations

import dataclasses
import inspect
import re
from collections import defaultdict
from pathlib import Path

import numpy as np

from unified_manip.envs.controllers import configs as ctl

ROOT = Path(__file__).resolve().parents[2]
#: The committed experiments that make up the benchmark page, in its order.
BENCHMARKS = ("benchmark", "benchmark_arm", "benchmark_robosuite", "benchmark_breadth_robosuite")
#: Where ``EnvConfig`` is documented, from a task page.
ENV_CONFIG_API = "../reference/api/envs.md#unified_manip.envs.config.EnvConfig"
REWARD_CONFIG_API = "../reference/api/rewards.md#unified_manip.envs.rewards.RewardConfig"


def _g(values) -> str:
    values = np.atleast_1d(values)
    return f"{values[0]:g}" if np.all(values == values[0]) else "(" + ", ".join(f"{v:g}" for v in values) + ")"


def scale(config: ctl.ControllerConfig) -> str:
    """What ``|a| = 1`` means under the mode, with its units."""
    if isinstance(config, ctl.JointTorque):
        return "the joint's torque limit, N m"
    if isinstance(config, ctl.JointPosition):
        return (
            "the ends of the joint's command range, rad" if config.band is None else f"q_reset ± {_g(config.band)} rad"
        )
    if isinstance(config, (ctl.JointDelta, ctl.JointTargetDelta)):
        if isinstance(config.max_delta, str):
            return "half the joint's command range per step, rad"
        return f"{_g(config.max_delta)} rad per step"
    if isinstance(config, (ctl.JointVelocity, ctl.IntegratedJointVelocity)):
        return f"{_g(config.max_velocity)} rad/s"
    if isinstance(config, ctl.EEDelta):
        return f"{config.step:g} m per step on x, y, z"
    return "the source's own (see below)"


def bounds(mode: dict) -> str:
    """A live action space's bounds, ``[-1.0, 1.0]`` (one value per side where every
    entry shares it)."""
    low = mode["low"][0] if len(mode["low"]) == 1 else mode["low"]
    high = mode["high"][0] if len(mode["high"]) == 1 else mode["high"]
    return f"[{low}, {high}]"


def box(mode: dict) -> str:
    """A live action space as Gymnasium prints it, ``Box(-1.0, 1.0, (4,), float32)``."""
    low, high = bounds(mode)[1:-1].split(", ", 1)
    return f"`Box({low}, {high}, ({mode['shape'][0]},), {mode['dtype']})`"


def action_tables(controllers, live: dict) -> list[str]:
    """Markdown, two tables: per mode the live action ``Box`` (bounds, shape, dtype), what
    ``a = ±1`` means in units and the ``observation`` length; then per mode what the action
    commands and the ``controller_options`` with their values here."""
    rows = [
        "| mode | action space | a = ±1 is | `observation` size |",
        "|---|---|---|---:|",
    ]
    for mode, config in controllers.items():
        m = live["modes"][mode]
        rows.append(f"| `{mode}` | {box(m)} | {scale(config)} | {m['observation']} |")
    rows += ["", "| mode | what `a` commands | `controller_options` (defaults here) |", "|---|---|---|"]
    for mode, config in controllers.items():
        params = ", ".join(f"`{name}={value!r}`" for name, value in config.parameters().items()) or "–"
        rows.append(f"| `{mode}` | {config.describe()} | {params} |")
    return rows


def term_formula(fn) -> str:
    """A reward term's function, written out."""
    if hasattr(fn, "gain"):  # rewards.Shaped
        x = "d_goal" if fn.of == "distance" else fn.of
        shaped = f"1 - tanh({fn.gain:g} · {x})"
        return f"{fn.gate} · ({shaped})" if fn.gate else shaped
    known = {"sparse": "success - 1", "success_bonus": "success", "action_penalty": "-Σa² (`action_sq`)"}
    name = getattr(fn, "__name__", "")
    if name in known:
        return known[name]
    doc = (getattr(fn, "__doc__", None) or repr(fn)).strip().splitlines()[0]
    return doc.split(":")[0].strip("`. ")  # a term set's own term: its docstring's formula


def reward_rows(term_set) -> list[str]:
    """Markdown rows: each ``reward_type``'s terms for a task of term set ``term_set``,
    with their scales, from the reward design the env builds (``EnvConfig.reward_design``)."""
    from unified_manip.envs.config import EnvConfig
    from unified_manip.envs.rewards import REWARD_TYPES

    rows = ['| `reward_type` | reward = sum of the terms (`info["reward_terms"]` key: scale × term) |', "|---|---|"]
    for reward_type in REWARD_TYPES:
        spec = EnvConfig(reward_type=reward_type).reward_design(term_set)
        terms = "; ".join(f"`{t.name}`: {t.scale:g} × ({term_formula(t.fn)})" for t in spec.terms)
        rows.append(f"| `{reward_type}` | {terms} |")
    return rows


def episode_end(spec, live: dict) -> list[str]:
    """Markdown: truncation by the time limit and by divergence, termination on success."""
    from unified_manip.envs.config import EnvConfig

    dt = live["dt"]
    seconds = spec.max_episode_steps * dt
    default = EnvConfig().terminate_on_success
    return [
        f"- **Truncation:** after **{spec.max_episode_steps} steps** of {dt * 1000:g} ms "
        f"({seconds:g} s simulated), by `gym.make`'s `TimeLimit` (`max_episode_steps`).",
        f"- **Termination:** never by default (`terminate_on_success={default}`): an episode runs to its "
        "time limit, as in Gymnasium-Robotics. With `terminate_on_success=True` it ends with "
        '`terminated=True` on the first step with `info["is_success"] == 1.0`.',
        "- **Divergence:** if the simulator diverges (a MuJoCo instability warning or a non-finite "
        'state), the step returns `truncated=True` with `info["sim_unstable"] = True` and the last '
        "finite observation; reset to go on.",
    ]


def _plain(text: str) -> str:
    """A docstring's reST on one line, as Markdown: roles and double backquotes as code."""
    text = re.sub(r":\w+:`~?([\w.]+)`", lambda m: f"`{m.group(1).rsplit('.', 1)[-1]}`", text)
    return " ".join(text.replace("``", "`").split())


def config_fields() -> list[tuple[str, object, str]]:
    """``(name, default, description)`` of every ``EnvConfig`` field but ``options``,
    the descriptions from its docstring's Attributes section."""
    from griffe import Docstring

    from unified_manip.envs.config import EnvConfig
    from unified_manip.envs.setup import CONFIG_FIELDS

    sections = Docstring(inspect.cleandoc(EnvConfig.__doc__)).parse("google")
    described = {a.name: a.description for s in sections if s.kind.value == "attributes" for a in s.value}
    out = []
    for field in dataclasses.fields(EnvConfig):
        if field.name in CONFIG_FIELDS:
            default = field.default if field.default is not dataclasses.MISSING else field.default_factory()
            out.append((field.name, default, _plain(described[field.name])))
    return out


def argument_rows(spec, live: dict) -> list[str]:
    """Markdown: every ``gym.make`` keyword with its default and the choices on this task."""
    from unified_manip.envs.cameras import IMAGE_GROUPS
    from unified_manip.envs.config import RENDER_MODES
    from unified_manip.envs.observations import PRESETS
    from unified_manip.envs.rewards import REWARD_TYPES

    def code(values) -> str:
        return ", ".join(f"`{v!r}`" for v in values)

    here = {
        "action_mode": code(spec.action_modes),
        "reward_type": code(REWARD_TYPES),
        "render_mode": "`None`, " + code(RENDER_MODES),
        "camera": code(spec.cameras) or "–",
        "observation": f"presets {code(PRESETS)}; groups {code(live['groups'])}; images {code(IMAGE_GROUPS)}",
        "controller_options": "per mode: see [action space](#action-space)",
    }
    rows = ["| keyword | default | on this task | meaning |", "|---|---|---|---|"]
    for name, default, text in config_fields():
        rows.append(f"| `{name}` | `{default!r}` | {here.get(name, '')} | {text} |")
    return rows


def _rows(task_id: str) -> dict[tuple, list]:
    from unified_manip.experiments.results import read_results

    groups: dict[tuple, list] = defaultdict(list)
    for name in BENCHMARKS:
        for r in read_results(ROOT / "results" / name / "results.csv"):
            if r["task"] == task_id:
                demos = r["demonstrations"]["episodes"] if r.get("demonstrations") else 0
                groups[(r["action_mode"], r["algo"], demos, r["steps"], name)].append(r)
    return groups


def benchmark_rows(task_id: str) -> list[str]:
    """Markdown: the task's rows of the benchmark (final success over seeds with the seeds'
    interval, and the target where its grid sets one); empty if the task has none."""
    from unified_manip.experiments.stats import seed_interval
    from unified_manip.experiments.targets import grid_targets

    groups = _rows(task_id)
    if not groups:
        return []
    rows = [
        "| mode | recipe | budget | seeds | final success [interval] | target | experiment |",
        "|---|---|---:|---:|---|---:|---|",
    ]
    for (mode, algo, demos, steps, name), runs in sorted(groups.items()):
        finals = [r["final_success_rate"] for r in runs]
        interval = seed_interval(finals).text()
        targets = grid_targets(ROOT / "results" / name / "grid.yaml")
        target = next((f"{t.success:.2f}" for t in targets if (t.task, t.action_mode) == (task_id, mode)), "–")
        recipe = f"{algo} + {demos} demos" if demos else algo
        rows.append(
            f"| `{mode}` | {recipe} | {steps // 1000}k | {len(runs)} | {np.mean(finals):.2f}"
            f"{' ' + interval if interval else ''} | {target} | `{name}` |"
        )
    return rows


def benchmark_summary(task_ids) -> str:
    """Markdown: every benchmark row of every task (as :func:`benchmark_rows`), one table,
    each task linked to its page (from the site's root)."""
    rows = [
        "| task | mode | recipe | budget | seeds | final success [interval] | target |",
        "|---|---|---|---:|---:|---|---:|",
    ]
    for task_id in task_ids:
        name = task_id.split("/", 1)[1]
        for row in benchmark_rows(task_id)[2:]:
            cells = row.strip("|").split(" | ")[:-1]  # without the experiment
            cells[4] = cells[4].split(" (", 1)[0]  # the interval without its label
            rows.append(f"| [{name}](tasks/{name}.md) | " + " | ".join(c.strip() for c in cells) + " |")
    return "\n".join(rows)
