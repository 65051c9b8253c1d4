"""Demonstrations as Minari datasets: record them, replay them exactly, convert them.

- :mod:`.recording` plays a policy and records each step with the simulator's full state
  (``unified-manip collect``);
- :mod:`.replay` replays a dataset from its states or its actions (``unified-manip replay``);
- :mod:`.convert` re-executes a dataset in another action mode (``unified-manip convert``),
  each step's action searched for by :mod:`.search` in a probe env (:mod:`.steps`: the
  initial guesses and the methods);
- :mod:`.store` reads and publishes datasets on disk (temporary name, then rename);
- :mod:`.versions` names the package versions a dataset was recorded with.

This layer imports only the env library (:mod:`unified_manip.envs`); a trained run's
policy comes in as a callable from the command line, which loads it through training.
Minari (``pip install "unified_manip[datasets]"``) is imported where it is used.
"""

from unified_manip.datasets.errors import DatasetError

__all__ = ["DatasetError"]
