"""Meta-World's benchmark task lists, by Meta-World name, as its ``metaworld.env_dict``
defines them (``MT10_V3``, ``MT50_V3``, ``ML10_V3``). Written out here, in Meta-World's
order, because reading them imports Meta-World and MuJoCo; a test compares them with
Meta-World's own."""

from __future__ import annotations

from unified_manip.envs.tasks.metaworld.tasks import TASKS

#: MT10: ten tasks trained together.
MT10 = (
    "reach-v3",
    "push-v3",
    "pick-place-v3",
    "door-open-v3",
    "drawer-open-v3",
    "drawer-close-v3",
    "button-press-topdown-v3",
    "peg-insert-side-v3",
    "window-open-v3",
    "window-close-v3",
)

#: ML10's ten meta-training tasks and five held-out meta-test tasks.
ML10_TRAIN = (
    "reach-v3",
    "push-v3",
    "pick-place-v3",
    "door-open-v3",
    "drawer-close-v3",
    "button-press-topdown-v3",
    "peg-insert-side-v3",
    "window-open-v3",
    "sweep-v3",
    "basketball-v3",
)
ML10_TEST = ("drawer-open-v3", "door-close-v3", "shelf-place-v3", "sweep-into-v3", "lever-pull-v3")

#: Every list by its name in ``metaworld:<name>``; MT50 is all 50 tasks.
LISTS: dict[str, tuple[str, ...]] = {
    "MT10": MT10,
    "MT50": tuple(TASKS),
    "ML10-train": ML10_TRAIN,
    "ML10-test": ML10_TEST,
}
