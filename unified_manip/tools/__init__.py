"""Measurement tools: env and training throughput, soak, levers, step response, checkpoint
size, exploration and the vector env benchmark.

Each module runs as ``python -m unified_manip.tools.<name>`` (``speed`` also as
``unified-manip speed``) and writes the JSON figures the documentation quotes. The layer
sits above training and experiments; nothing below imports it.
"""
