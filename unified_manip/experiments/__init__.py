"""Experiments: grids of training runs, the bench that trains them, their results and the
reports and figures drawn from them.

``grid`` reads and validates grid files, ``bench`` trains a grid (locally or on Ray),
``results`` owns ``results.csv``, ``report``/``figures``/``plot``/``curves``/``stats``/
``targets`` turn results into Markdown and figures, and ``sanity`` checks dense rewards.
The layer imports the env library and training; neither imports it.
"""
