"""Keyword arguments to a validated env, in one place.

``gym.make(ID, **kwargs)``, ``gym.make_vec(ID, **kwargs)`` and the trainer all go through
:func:`env_setup`: it splits the keyword arguments into :class:`~unified_manip.envs.config.EnvConfig`'s
fields and the family's own options, checks the action mode against the task, and
resolves the mode's controller config once. The backends are then built from that
:class:`EnvSetup`, so every entry point accepts the same arguments with the same errors.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from unified_manip.envs.cameras import resolve_camera
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.registry import TaskSpec, get_task

if TYPE_CHECKING:
    from unified_manip.envs.backend import Backend

#: ``EnvConfig``'s fields a caller passes by name; any other keyword is a family option.
CONFIG_FIELDS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(EnvConfig) if f.name != "options")


@dataclass(frozen=True)
class EnvSetup:
    """One task's validated config and its resolved action mode.

    Attributes:
        task: The task's spec.
        config: The validated env options.
        controller: The action mode's controller config, with ``controller_options`` applied.
    """

    task: TaskSpec
    config: EnvConfig
    controller: ControllerConfig

    def build_backend(self) -> Backend:
        """A new backend of the task, built from :attr:`config` and :attr:`controller`.

        Raises:
            unified_manip.extras.MissingExtra: The family's extra is not installed.
            unified_manip.envs.mujoco_version.UnsupportedMuJoCo: The installed MuJoCo is
                outside the supported range.
        """
        self.task.require_installed()  # before the family's simulator is imported
        return self.task.make_backend(self.config, self.controller)


def env_setup(task_id: str, **kwargs: Any) -> EnvSetup:
    """The :class:`EnvSetup` of ``gym.make(task_id, **kwargs)``.

    Args:
        task_id: A registered ID.
        **kwargs: :data:`CONFIG_FIELDS` by name; anything else goes to the family as an option.

    Raises:
        ValueError: An unknown ID, action mode, reward type, controller option or camera,
            or a mode the task does not support (each with the valid choices).
        TypeError: A field of the wrong type.

    Only the arguments are checked here (a grid validates its cells so without the
    simulators); :meth:`EnvSetup.build_backend` checks that the family is installed.
    """
    task = get_task(task_id)
    fields = {k: kwargs.pop(k) for k in CONFIG_FIELDS if k in kwargs}
    config = EnvConfig(**fields, options=kwargs)
    config.require_supported(task.id, task.action_modes)
    task.terms.check_terminations(config.terminate_on, task.id)
    if config.camera is not None:
        resolve_camera(config.camera, task.cameras, task.id)
    return EnvSetup(task, config, config.mode_config(task.controllers))
