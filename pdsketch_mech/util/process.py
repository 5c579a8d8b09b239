"""What a command-line process knows about itself: when it started, and how Ctrl-C ends it.

- Time limits (`plan --timeout`) and reported times count from the start of the process, as
  a user with a stopwatch does: interpreter start-up and imports included.
- Ctrl-C ends a command within `GRACE` seconds with exit status 130 and the line
  `interrupted`, at any moment. While the command's `main` runs, the handler raises
  `KeyboardInterrupt` as Python's default does (`commands.common.run` turns it into the line and the
  status, after `finally` blocks have run) and also starts a watchdog: some libraries
  swallow the exception — trimesh imports its optional dependencies inside
  `except BaseException`, so a Ctrl-C during its import vanished and the run went on to
  its full time limit — and then the watchdog ends the process itself. Before `main` runs
  (module imports) and after it returns, there is nothing to clean up: the process ends
  at once.

Only processes running one of our commands (`python -m pdsketch_mech.X`) install the
handler (the package's `__init__` does it, after `early.py`'s, which covers the imports
before it); a library user's process is left alone.
"""
from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from typing import Iterator, Optional

from .early import EXIT_INTERRUPTED, command_module, is_command  # noqa: F401 (command_module: part of the API)

GRACE = 0.15          # seconds a KeyboardInterrupt gets to end the process on its own

_interrupted = threading.Event()
_reported = threading.Event()
_report_fd = 2                # where `interrupted` goes: the real stderr, also while fd 2 is silenced
_in_main = threading.Event()  # KeyboardInterrupt is only raised where `commands.common.run` catches it


def _process_age() -> Optional[float]:
    """Seconds since this process started (Linux: /proc/self/stat), or None if unknown."""
    try:
        with open("/proc/self/stat", "rb") as handle:
            fields = handle.read().rsplit(b")", 1)[1].split()
        start_ticks = int(fields[19])  # field 22 (starttime), counted after the ")" of field 2
        return time.clock_gettime(time.CLOCK_BOOTTIME) - start_ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, AttributeError):
        return None


_STARTED = time.perf_counter() - max(0.0, _process_age() or 0.0)


def started() -> float:
    """The `time.perf_counter()` value at which a command's clock starts: the start of the
    process for a command, the call itself for a library caller (a test calling `main`)."""
    return _STARTED if is_command() else time.perf_counter()


def limit_blas_threads() -> None:
    """One BLAS thread for numpy, unless the user chose otherwise (OPENBLAS_NUM_THREADS, read
    when numpy is first imported: the package's `__init__` calls this before any module
    imports numpy). A plan's matrices are small (a classifier's 16 x 384 by 384 x 128), and
    OpenBLAS's threads spin against the other plan of a two-worker benchmark and against
    PyBullet: on two busy cores such a product is several times slower with two threads than
    with one."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def install_interrupt_handler() -> None:
    """Ctrl-C raises KeyboardInterrupt and guarantees exit 130 within `GRACE` seconds."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, _on_interrupt)


@contextlib.contextmanager
def main_running() -> Iterator[None]:
    """Marks the span in which a Ctrl-C is raised as KeyboardInterrupt (see the module doc)."""
    _in_main.set()
    try:
        yield
    finally:
        _in_main.clear()


def interrupted() -> bool:
    """Whether Ctrl-C was pressed."""
    return _interrupted.is_set()


def report_interrupt() -> int:
    """Print `interrupted` (once) and return the exit status, for the KeyboardInterrupt handler."""
    if not _reported.is_set():
        _reported.set()
        print("interrupted", file=sys.stderr, flush=True)
    return EXIT_INTERRUPTED


def _on_interrupt(signum, frame) -> None:
    if _interrupted.is_set():
        return  # a second Ctrl-C: the watchdog is already counting
    _interrupted.set()
    # Before main, or while a module is being imported, end at once: an exception raised into
    # a native extension's initialisation (PyBullet, OMPL) aborts the process (SIGABRT)
    # instead of unwinding, and an import holds nothing of the user's.
    if not _in_main.is_set() or _importing(frame):
        _force_exit()
    watchdog = threading.Timer(GRACE, _force_exit)
    watchdog.daemon = True
    watchdog.start()
    raise KeyboardInterrupt


def _importing(frame) -> bool:
    """Is the interrupted code inside an import (a frame of importlib's bootstrap)?"""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


@contextlib.contextmanager
def reporting_to(fd: int) -> Iterator[None]:
    """While fd 2 is sent elsewhere (quiet_pybullet silences PyBullet's banner), a Ctrl-C's
    `interrupted` line goes to `fd`, a duplicate of the real stderr."""
    global _report_fd
    before, _report_fd = _report_fd, fd
    try:
        yield
    finally:
        _report_fd = before


def _force_exit() -> None:
    """The KeyboardInterrupt was swallowed (or exit is slow): end the process now."""
    if not _reported.is_set():
        _reported.set()
        os.write(_report_fd, b"interrupted\n")
    kill_children()
    os._exit(EXIT_INTERRUPTED)


def kill_children() -> None:
    """End the process's worker processes (`--workers K`) at once: they ignore Ctrl-C, and
    after an os._exit they would run on through their episode, holding the command's output
    pipes open (a pool's own shutdown waits on them, and on a loaded machine outlasts GRACE).
    Multiprocessing's resource tracker may then warn of the pool's semaphores."""
    multiprocessing = sys.modules.get("multiprocessing")
    if multiprocessing is None:
        return
    try:
        children = multiprocessing.active_children()
    except Exception:  # the main thread may be stopping them too; its list can change under us
        return
    for child in children:
        try:
            child.kill()
        except Exception:
            pass
