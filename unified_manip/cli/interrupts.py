"""Ctrl-C on the command line: one line on stderr and exit status 130, however deep in an
import or a C library the signal lands.

Python turns SIGINT into ``KeyboardInterrupt``, but a C extension that is importing, or a
ctypes call, can turn that into another error (``ImportError: initialization failed``,
``ctypes.ArgumentError: ... KeyboardInterrupt``). So the command line notes the signal
itself, and any error that follows it is the interrupt.

An object the signal cut off half-built (a renderer's GL context, say) can fail in its
``__del__`` as the stack unwinds, and Python prints such errors with a traceback ("Exception
ignored in ..."). After the signal those are the interrupt's, so they are not printed.
"""

from __future__ import annotations

import ctypes
import gc
import signal
import sys
import threading
from contextlib import contextmanager
from typing import Iterator


class CtrlC:
    """A SIGINT handler that raises ``KeyboardInterrupt``, as Python's own does, and
    remembers that it did."""

    def __init__(self) -> None:
        self.pressed = False

    def __call__(self, signum, frame) -> None:
        self.pressed = True
        sys.unraisablehook = _after_the_interrupt
        raise KeyboardInterrupt

    def caused(self, err: BaseException) -> bool:
        """Whether ``err`` is Ctrl-C: a ``KeyboardInterrupt``, one in its chain, or any
        error raised after the signal came."""
        return self.pressed or _chained_interrupt(err)


@contextmanager
def noting_ctrl_c() -> Iterator[CtrlC]:
    """Install a :class:`CtrlC` while the block runs, where Python's own handler is
    installed (not where SIGINT is ignored, as in a background job, nor off the main
    thread), and restore the previous handler after."""
    ctrl_c = CtrlC()
    install = (
        threading.current_thread() is threading.main_thread()
        and signal.getsignal(signal.SIGINT) is signal.default_int_handler
    )
    previous = signal.signal(signal.SIGINT, ctrl_c) if install else None
    hook = sys.unraisablehook
    try:
        yield ctrl_c
    finally:
        if install:
            signal.signal(signal.SIGINT, previous)
        if ctrl_c.pressed:  # what the interrupt left unreachable goes now, quietly
            gc.collect()
        sys.unraisablehook = hook


def _after_the_interrupt(unraisable) -> None:
    """``sys.unraisablehook`` once Ctrl-C came: an error in a finaliser is the interrupt's."""


def _chained_interrupt(err: BaseException | None) -> bool:
    seen = set()
    while err is not None and id(err) not in seen:
        if isinstance(err, KeyboardInterrupt):
            return True
        seen.add(id(err))
        err = err.__cause__ or err.__context__
    return False


def exit_normally_after_interrupt() -> None:
    """Let the process exit with the status returned, not by SIGINT. CPython kills itself
    with SIGINT at exit (status -2 to a parent process) when a KeyboardInterrupt once left
    code run through ``PyRun_String``, even if it was caught later; MuJoCo's bindings run
    such code while they import. Running any code through the same call clears that."""
    ctypes.pythonapi.PyRun_SimpleString(b"pass")
