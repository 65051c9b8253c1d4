"""Portable floating point for the tests that compare results bit for bit across machines.

The last bits of a rollout depend on which code paths the CPU selects at run time:
OpenBLAS's kernel (``action @ action``, mink's QP objective, robosuite's controllers),
numpy's SIMD loops, glibc's libm variants (MuJoCo's ``sin``/``exp``) and numba's target
(robosuite). A process started with :data:`PORTABLE_ENV` pins every one of them to its
generic x86-64 code, so that its rollouts are the same on any x86-64 CPU with the pinned
libraries: the golden rollouts (``tests/envs/golden.py``) and the committed example
datasets (``tests/datasets/test_examples.py``) are played so.
"""

from __future__ import annotations

import ctypes
import glob
import os
import subprocess

import numpy as np

#: numpy's run-time dispatched SIMD features (all of numpy 1.26's x86 ones, and numpy 2.4's
#: X86_V3/X86_V4 groups): disabled, numpy runs its baseline loops (SSE3 on 1.26, x86-64-v2
#: on 2.4). Names the CPU or the numpy build lacks are ignored.
_NUMPY_DISPATCH = (
    "SSSE3 SSE41 POPCNT SSE42 AVX F16C FMA3 AVX2 AVX512F AVX512CD AVX512_KNL AVX512_KNM "
    "AVX512_SKX AVX512_CLX AVX512_CNL AVX512_ICL AVX512_SPR X86_V3 X86_V4"
)
#: The OpenBLAS kernel set ``OPENBLAS_CORETYPE=Prescott`` selects: Prescott in numpy 1.26's
#: OpenBLAS 0.3.23; numpy 2.4's scipy-openblas 0.3.31 has no Prescott set and takes
#: Katmai's, its generic x86 one.
_GENERIC_CORES = ("Prescott", "Katmai")
#: The environment of the process that plays golden rollouts. Each variable must be set
#: before the process starts (glibc) or before the library loads (the others).
PORTABLE_ENV = {
    "OPENBLAS_CORETYPE": "Prescott",  # OpenBLAS's generic SSE3 kernels (numpy's and scipy's copies)
    "OPENBLAS_NUM_THREADS": "1",
    "NPY_DISABLE_CPU_FEATURES": _NUMPY_DISPATCH,
    "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4,-AVX512F",  # libm's SSE2 variants
    "NUMBA_CPU_NAME": "generic",  # robosuite's numba kernels
    "MUJOCO_GL": "egl",
}


def is_portable() -> bool:
    """True if this process runs with :data:`PORTABLE_ENV` in effect."""
    return all(os.environ.get(k) == v for k, v in PORTABLE_ENV.items())


def check_portable() -> None:
    """Raise unless numpy's SIMD dispatch and its OpenBLAS kernel are the pinned ones
    (they are fixed when numpy loads, so setting the variables later has no effect)."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:  # numpy 1.26
        from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    # Only the features this numpy build has kernels for matter: a newer CPU's extra ones
    # (AVX512_SPR on Sapphire Rapids, for numpy 1.26) stay "active" and are never used.
    active = sorted(f for f in __cpu_dispatch__ if __cpu_features__.get(f))
    libs = glob.glob(os.path.join(os.path.dirname(np.__file__), os.pardir, "numpy.libs", "lib*openblas*"))
    core = None
    if libs:
        lib = ctypes.CDLL(libs[0])  # numpy 1.26's libopenblas64_ or numpy 2's libscipy_openblas64_
        corename = getattr(lib, "openblas_get_corename64_", None) or lib.scipy_openblas_get_corename64_
        corename.restype = ctypes.c_char_p
        core = corename().decode()
    if active or core not in _GENERIC_CORES:
        raise RuntimeError(
            f"golden rollouts need generic floating point: numpy dispatches {active}, OpenBLAS "
            f"kernel {core!r}; start the process with tests/portable.py's PORTABLE_ENV"
        )


def run(cmd: list[str], timeout: float) -> subprocess.CompletedProcess:
    """``cmd`` (``sys.executable`` first) in a child process with :data:`PORTABLE_ENV`."""
    return subprocess.run(cmd, env={**os.environ, **PORTABLE_ENV}, capture_output=True, text=True, timeout=timeout)


__all__ = ["PORTABLE_ENV", "check_portable", "is_portable", "run"]
