"""Process gauges for the soak benchmark: resident memory, open file descriptors, threads
and live MuJoCo GL contexts of this process, read from ``/proc/self`` (Linux)."""

from __future__ import annotations

import gc
import os


def rss_mb() -> float:
    gc.collect()
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def open_fds() -> int:
    return len(os.listdir("/proc/self/fd"))


def threads() -> int:
    return len(os.listdir("/proc/self/task"))


def gl_contexts() -> int:
    """Live MuJoCo GL contexts (``mujoco.egl`` / ``glfw`` / ``osmesa`` ``GLContext``)."""
    gc.collect()
    return sum(
        1 for o in gc.get_objects() if type(o).__name__ == "GLContext" and type(o).__module__.startswith("mujoco")
    )
