"""Domain randomisation: terms that check themselves, entities of every family, seeded
draws (same seed, same rollout, bit for bit, under every preset), the native vector env
equal to the single env, nominal values never compounded, solids that change shape and
still rest on the table, interval draws, and exact replay of a recorded dataset."""

from __future__ import annotations

import pickle
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import SyncVectorEnv

from unified_manip.envs.randomization import PRESETS, RandomizationTerm, distribution_for, preset_terms, term_from
from unified_manip.envs.registry import TASKS

ARM = "UnifiedManip/Arm4PickAndPlace-v0"
KITCHEN = "UnifiedManip/FrankaKitchen-v0"
TRAINING_PRESETS = ("dynamics", "objects", "visual", "all")
EVERY_PRESET = (*TRAINING_PRESETS, *(f"{p}:extreme" for p in TRAINING_PRESETS))


def _make(task_id: str = ARM, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gym.make(task_id, **kwargs)


def _rollout(env, seed: int, steps: int):
    rng = np.random.default_rng(seed)
    obs, info = env.reset(seed=seed)
    out = [obs["observation"].copy()]
    infos = [info]
    for _ in range(steps):
        obs, reward, _, _, info = env.step(rng.uniform(-1, 1, env.action_space.shape))
        out.append(np.append(obs["observation"], reward))
        infos.append(info)
    return np.stack(out[1:]), out[0], infos


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(field="weight"), "unknown randomization field 'weight'; expected one of 'size', 'mass'"),
        (dict(field="mass", distribution="beta"), "unknown distribution 'beta'; expected one of 'uniform'"),
        (dict(field="mass", operation="times"), "unknown operation 'times' for field 'mass'; expected one of 'abs'"),
        (
            dict(field="camera_pose", operation="scale"),
            "operation 'scale' for field 'camera_pose'; expected one of 'add'",
        ),
        (dict(field="mass", mode="often"), "unknown mode 'often'; expected one of 'startup', 'reset', 'interval'"),
        (dict(field="mass", range=(2.0, 1.0)), "range (2.0, 1.0) is inverted; expected (low, high) with low <= high"),
        (dict(field="mass", range=(0.0, 1.0)), "object.mass: range (0.0, 1.0) gives factors below the valid ones"),
        (dict(field="size", range=(-0.01, 0.02), operation="abs"), "size must stay above 0"),
        (dict(field="friction", range=(-0.5, 1.0)), "friction must stay at least 0"),
        (dict(field="mass", range=(1.0, 0.1), distribution="gaussian"), "gaussian is unbounded"),
        (dict(field="mass", range=(0.0, 2.0), distribution="log_uniform"), "a log_uniform range must be above 0"),
        (dict(field="mass", mode="interval"), "mode 'interval' needs every >= 1"),
        (dict(field="mass", every=3), "every=3 is for mode 'interval' only"),
        (dict(field="mass", range=(0.5, 2.0), exclude=(0.1, 1.0)), "exclude (0.1, 1.0) must lie inside range"),
        (dict(field="shape", operation="abs", shapes=("cube",)), "unknown shape 'cube'; expected one of 'box'"),
        (dict(field="shape", operation="abs"), "a 'shape' term needs shapes"),
        (dict(field="mass", range="heavy"), "range must be a pair of numbers (low, high)"),
    ],
)
def test_a_bad_term_fails_on_construction_naming_the_valid_choices(kwargs, message):
    with pytest.raises(ValueError) as err:
        RandomizationTerm("object", **kwargs)
    assert message in str(err.value)
    assert "\n" not in str(err.value)


def test_an_unknown_preset_or_suffix_names_the_valid_ones():
    with pytest.raises(ValueError, match=r"unknown randomization preset 'heavy'; expected one of 'none', 'dynamics'"):
        _make(randomization="heavy")
    with pytest.raises(ValueError, match=r"unknown suffix 'wild' of preset 'objects'; expected one of 'extreme'"):
        _make(randomization="objects:wild")
    with pytest.raises(ValueError, match=r"unknown randomization term key 'entty'"):
        _make(randomization=[{"entty": "object", "field": "mass"}])


@pytest.mark.parametrize(
    "task_id, term, message",
    [
        (ARM, dict(entity="cube", field="mass", range=(0.5, 2.0)), "has no entity 'cube'; expected one of 'object'"),
        (ARM, dict(entity="light", field="mass", range=(0.5, 2.0)), "entity 'light' has no bodies, which field 'mass'"),
        (
            ARM,
            dict(entity="object", field="friction", range=(-1.5, 0.0), operation="add"),
            "object.friction add range (-1.5, 0.0) takes the smallest nominal 1 to -0.5; friction must stay at least 0",
        ),
        (
            "UnifiedManip/PickPlaceCan-v0",
            dict(entity="object", field="size", range=(0.9, 1.1)),
            "geom 'Can_g0' is a mesh or plane, whose size is fixed when the model is compiled",
        ),
        (
            "UnifiedManip/HandManipulateBlock-v0",
            dict(entity="object", field="shape", operation="abs", shapes=("sphere",)),
            "entity 'object' is not a primitive solid the family lets change shape",
        ),
    ],
)
def test_a_term_the_task_cannot_take_fails_at_make(task_id, term, message):
    with pytest.raises(ValueError) as err:
        _make(task_id, randomization=[term])
    assert message in str(err.value)


def test_a_pushed_object_keeps_its_shape():
    env = _make("UnifiedManip/Arm4Push-v0", randomization="objects")
    try:
        assert "object.shape" not in {t.label for t in env.unwrapped.randomizer.terms}
        assert any("keeps its shape" in s for s in env.unwrapped.randomizer.skipped)
    finally:
        env.close()
    sphere = dict(entity="object", field="shape", operation="abs", shapes=("box", "sphere"))
    with pytest.raises(ValueError, match=r"entity 'object' cannot become a sphere; it takes box"):
        _make("UnifiedManip/FetchPush-v0", randomization=[sphere])


def test_a_preset_that_applies_to_nothing_says_why():
    with pytest.raises(
        ValueError, match=r"'objects' has no term that applies to UnifiedManip/Arm4Reach-v0.*no 'object'"
    ):
        _make("UnifiedManip/Arm4Reach-v0", randomization="objects")


# ---------------------------------------------------------------------- presets and entities
def test_every_preset_has_an_extreme_counterpart_beyond_its_ranges():
    for name in TRAINING_PRESETS:
        train, extreme = preset_terms(name), preset_terms(f"{name}:extreme")
        assert [t.label for t in train] == [t.label for t in extreme]
        for t, x in zip(train, extreme):
            if t.field == "shape":
                continue
            assert x.exclude == t.range  # never a value seen in training
            assert x.range[0] < t.range[0] and x.range[1] > t.range[1]
    assert preset_terms("in-range".join(("objects:", ""))) == PRESETS["objects"]
    assert distribution_for("dynamics+objects", "extreme") == "dynamics:extreme+objects:extreme"
    assert distribution_for("dynamics+objects", "in-range") == "dynamics+objects"
    assert distribution_for("objects", "default") == "none"


@pytest.mark.parametrize(
    "task_id, expected",
    [
        (ARM, {"object.shape", "object.size", "object.mass", "object.friction", "robot.damping", "table.rgba"}),
        ("UnifiedManip/FetchPickAndPlace-v0", {"object.shape", "object.size", "table.friction", "camera.camera_pose"}),
        ("UnifiedManip/HandManipulateBlock-v0", {"object.mass", "robot.actuator_gain", "light.light"}),
        ("UnifiedManip/Lift-v0", {"object.shape", "object.size", "table.rgba", "robot.armature"}),
        (KITCHEN, {"object.mass", "table.friction", "robot.actuator_gain", "light.light"}),
    ],
)
def test_preset_all_reaches_every_family_through_its_entities(task_id, expected):
    env = _make(
        task_id,
        action_mode="ee_delta" if task_id != "UnifiedManip/HandManipulateBlock-v0" else "native",
        randomization="all",
    )
    try:
        labels = {t.label for t in env.unwrapped.randomizer.terms}
        assert expected <= labels
        _, info = env.reset(seed=0)
        assert set(info["randomization"]) == set(env.unwrapped.randomization_state())
    finally:
        env.close()


def test_every_task_declares_entities():
    families = ("arm4", "fetch", "shadow_hand", "robosuite", "kitchen")
    assert all(spec.entities for spec in TASKS.values() if spec.family in families)


# ---------------------------------------------------------------------- none changes nothing
def test_none_draws_nothing_and_adds_no_info_key():
    plain, none = _make(action_mode="ee_delta"), _make(action_mode="ee_delta", randomization="none")
    try:
        assert none.unwrapped.randomizer is None and none.unwrapped.randomization_state() == {}
        a, a0, infos_a = _rollout(plain, 3, 20)
        b, b0, infos_b = _rollout(none, 3, 20)
        np.testing.assert_array_equal(a, b)
        assert all("randomization" not in i for i in infos_b)
        assert [set(i) for i in infos_a] == [set(i) for i in infos_b]
        state = none.unwrapped.np_random.bit_generator.state
        assert state == plain.unwrapped.np_random.bit_generator.state
    finally:
        plain.close()
        none.close()


# ---------------------------------------------------------------------- seeding
@pytest.mark.parametrize("preset", EVERY_PRESET)
def test_the_same_seed_gives_the_same_rollout_under_every_preset(preset):
    envs = [_make(action_mode="ee_delta", randomization=preset) for _ in range(2)]
    try:
        a, a0, infos = _rollout(envs[0], 11, 40)
        b, b0, _ = _rollout(envs[1], 11, 40)
        np.testing.assert_array_equal(a0, b0)
        np.testing.assert_array_equal(a, b)
        assert infos[0]["randomization"] == envs[1].unwrapped.randomization_state()
        envs[1].reset(seed=12)
        assert envs[1].unwrapped.randomization_state() != infos[0]["randomization"]
    finally:
        for e in envs:
            e.close()


@pytest.mark.parametrize("task_id", ["UnifiedManip/FetchPickAndPlace-v0", "UnifiedManip/Lift-v0", KITCHEN])
def test_the_same_seed_gives_the_same_rollout_on_other_families(task_id):
    envs = [_make(task_id, action_mode="ee_delta", randomization="all") for _ in range(2)]
    try:
        a, _, _ = _rollout(envs[0], 5, 15)
        b, _, _ = _rollout(envs[1], 5, 15)
        np.testing.assert_array_equal(a, b)
    finally:
        for e in envs:
            e.close()


@pytest.mark.parametrize("preset", ["dynamics", "objects", "visual", "all:extreme"])
@pytest.mark.parametrize(
    "task_id, mode", [(ARM, "ee_delta"), (ARM, "joint_delta"), ("UnifiedManip/FetchPush-v0", "ee_delta")]
)
def test_the_native_vector_env_draws_per_env_and_equals_the_single_env(task_id, mode, preset):
    kwargs = dict(action_mode=mode, randomization=preset)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        native = gym.make_vec(task_id, num_envs=3, **kwargs)
        single = SyncVectorEnv([lambda: gym.make(task_id, **kwargs)] * 3)
    try:
        assert type(native).__name__ == "NativeVectorEnv"
        o1, i1 = native.reset(seed=4)
        o2, i2 = single.reset(seed=4)
        for key in o1:
            np.testing.assert_array_equal(o1[key], o2[key])
        for key, value in i2["randomization"].items():
            if not key.startswith("_"):
                np.testing.assert_array_equal(i1["randomization"][key], value)
        assert len({tuple(native.randomization_state(i).values()) for i in range(3)}) == 3  # each env its own
        rng = np.random.default_rng(0)
        for _ in range(TASKS[task_id].max_episode_steps + 5):  # through an autoreset
            a = rng.uniform(-1, 1, native.action_space.shape)
            r1, r2 = native.step(a), single.step(a)
            for key in r1[0]:
                np.testing.assert_array_equal(r1[0][key], r2[0][key])
            np.testing.assert_array_equal(r1[1], r2[1])
            assert ("randomization" in r1[4]) == ("randomization" in r2[4])
    finally:
        native.close()
        single.close()


# ---------------------------------------------------------------------- what a draw writes
def test_draws_start_from_the_nominal_values_every_time():
    env = _make(randomization=[RandomizationTerm("object", "mass", (0.5, 2.0), "log_uniform")])
    try:
        model, body = env.unwrapped.backend.model, env.unwrapped.backend.model.body("object").id
        masses = []
        for seed in range(30):
            _, info = env.reset(seed=seed)
            masses.append(model.body_mass[body])
            assert model.body_mass[body] == pytest.approx(0.1 * info["randomization"]["object.mass"])
        assert 0.05 <= min(masses) < 0.08 and 0.15 < max(masses) <= 0.2  # no compounding over 30 draws
    finally:
        env.close()


def test_startup_terms_keep_their_values_until_a_seeded_reset():
    term = RandomizationTerm("object", "friction", (0.5, 1.5), mode="startup")
    env = _make(randomization=[term])
    try:
        _, info = env.reset(seed=1)
        first = info["randomization"]["object.friction"]
        assert env.reset()[1]["randomization"]["object.friction"] == first
        assert env.reset(seed=2)[1]["randomization"]["object.friction"] != first
        assert env.reset(seed=1)[1]["randomization"]["object.friction"] == first
    finally:
        env.close()


def test_interval_terms_draw_every_k_steps():
    term = RandomizationTerm("robot", "damping", (0.5, 2.0), mode="interval", every=5)
    env = _make(action_mode="ee_delta", randomization=[term])
    try:
        _, _, infos = _rollout(env, 0, 16)
        drew = [t for t, info in enumerate(infos) if "randomization" in info]
        assert drew == [0, 6, 11, 16]  # the reset, then before steps 6, 11 and 16
    finally:
        env.close()


@pytest.mark.parametrize("shape, size", [("box", 1.2), ("cylinder", 0.8), ("sphere", 1.2), ("box", 0.8)])
def test_a_solid_changes_shape_and_rests_on_the_table(shape, size, request):
    import mujoco

    if shape == "cylinder" and tuple(int(x) for x in mujoco.__version__.split(".")[:2]) < (3, 9):
        # Measured on 3.3.0: the 0.8x cylinder still rocks at 0.5 rad/s after 25 and 75 steps.
        request.applymarker(pytest.mark.xfail(strict=True, reason="MuJoCo 3.3.0's cylinder contact does not settle"))
    terms = [
        RandomizationTerm("object", "shape", operation="abs", shapes=(shape,)),
        RandomizationTerm("object", "size", (size, size)),
    ]
    env = _make(action_mode="ee_delta", randomization=terms)
    try:
        env.reset(seed=0)
        b = env.unwrapped.backend
        m, g = b.model, b.model.geom("object_geom").id
        assert m.geom_type[g] == {"box": 6, "cylinder": 5, "sphere": 2}[shape]
        for _ in range(25):
            env.step(np.array([0.0, 0.0, 0.0, 1.0]))
        z = float(b.data.qpos[8])
        assert z == pytest.approx(0.42 + 0.025 * size, abs=1.5e-3)  # resting on the table top, not in it
        assert float(np.abs(b.data.qvel[6:12]).max()) < 0.05
    finally:
        env.close()


def test_visual_terms_change_what_the_camera_sees():
    frames = []
    for preset in ("none", "visual"):
        env = _make(observation=["default", "rgb"], image_size=32, randomization=preset)
        try:
            frames.append(env.reset(seed=0)[0]["rgb"].astype(int))
        finally:
            env.close()
    assert np.abs(frames[0] - frames[1]).mean() > 1.0


def test_term_mappings_round_trip():
    for term in preset_terms("all:extreme"):
        assert term_from(term.as_dict()) == term


def test_pickling_keeps_the_randomised_model():
    env = _make(action_mode="ee_delta", randomization="all")
    try:
        env.reset(seed=0)
        copy = pickle.loads(pickle.dumps(env))
        a = np.array([0.3, -0.2, 0.1, 1.0])
        for _ in range(5):
            r1, r2 = env.step(a), copy.step(a)
        np.testing.assert_array_equal(r1[0]["observation"], r2[0]["observation"])
        assert copy.unwrapped.randomization_state() == env.unwrapped.randomization_state()
    finally:
        env.close()


@pytest.mark.robosuite
def test_robosuite_refuses_to_pickle_under_randomization():
    env = _make("UnifiedManip/Lift-v0", randomization="objects")
    try:
        env.reset(seed=0)
        with pytest.raises(TypeError, match="cannot be pickled under randomization"):
            pickle.dumps(env)
    finally:
        env.close()


def test_a_dataset_recorded_under_a_preset_records_it_and_replays_exactly(tmp_path):
    from unified_manip.datasets import store
    from unified_manip.datasets.policies import scripted
    from unified_manip.datasets.recording import collect
    from unified_manip.datasets.replay import replay

    out = tmp_path / "arm-objects-v0"
    kwargs = {"action_mode": "ee_delta", "randomization": "all"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        collect(ARM, kwargs, scripted, "scripted", "scripted", 2, out, seed=3, progress=False)
    dataset = store.open_dataset(out)
    meta = store.metadata(dataset)
    assert meta["env_kwargs"] == kwargs
    assert [f"{t['entity']}.{t['field']}" for t in meta["randomization"]["terms"]] == [
        t.label for t in preset_terms("all")
    ]
    episodes = list(dataset.iterate_episodes())
    masses = [float(ep.infos["randomization"]["object.mass"][0]) for ep in episodes]
    assert len(set(masses)) == 2  # each episode's own draw, in its reset's row
    for from_actions in (False, True):
        report = replay(out, from_actions=from_actions, progress=False)
        assert [(e.first_departure, e.max_deviation) for e in report.episodes] == [(None, 0.0), (None, 0.0)]
