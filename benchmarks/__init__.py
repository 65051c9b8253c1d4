"""The measurement tools: env and training throughput, soak, levers, step response,
checkpoint size, exploration, the vector env benchmark, camera cost and the dataset
conversion table. Not part of the installed package: run them from a checkout's root as
``python -m benchmarks.<name>`` (``--help`` for the options).

They measure the package from outside (``gym.make``, the env's ``backend`` property, the
registry); nothing in ``unified_manip`` imports them. A tool's ``--json`` figures go where it
is told; the committed ones, which the documentation quotes, are in ``benchmarks/out/``.
"""
