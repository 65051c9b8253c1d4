"""Faster updates that keep the algorithm: the ``compile_loss`` run setting.

``compile_loss: true`` runs TQC's quantile Huber loss (sb3-contrib's ``quantile_huber_loss``)
through ``torch.compile`` while the run trains. Measured inside SB3's real TQC update of the
benchmark recipe on one core (``python -m benchmarks.update_speed``,
``benchmarks/out/update_speed.json``): 85.8 ms per update eagerly, 58.1 ms compiled (1.48x). The loss is
the same function; compiled kernels may round differently in the last bits, so a compiled
run is not bit-identical to an eager one, and ``config.yaml`` records the setting.
"""

from __future__ import annotations

import contextlib
from typing import Iterator


class SpeedupError(ValueError):
    """A speed-up asked of an algorithm it does not apply to (one-line error)."""


def check(algo_class: str, compile_loss: bool) -> None:
    """Refuse ``compile_loss`` for an algorithm without a loss it knows how to compile."""
    if compile_loss and algo_class != "TQC":
        raise SpeedupError(
            f"compile_loss compiles TQC's quantile Huber loss; this run's algorithm is {algo_class}, expected a TQC "
            "algorithm (tqc_her)"
        )


@contextlib.contextmanager
def compiled_loss(enabled: bool) -> Iterator[None]:
    """While the block runs, TQC's training step calls the compiled quantile loss; the eager
    one is back afterwards (a process may train several runs)."""
    if not enabled:
        yield
        return
    import torch
    from sb3_contrib.tqc import tqc as tqc_module

    eager = tqc_module.quantile_huber_loss
    tqc_module.quantile_huber_loss = torch.compile(eager)
    try:
        yield
    finally:
        tqc_module.quantile_huber_loss = eager
