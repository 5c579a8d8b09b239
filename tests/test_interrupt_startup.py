"""Ctrl-C in the first milliseconds of a command exits 130 with `interrupted`, no traceback:
while the package's first modules import (before `process` installs its handler), and at
a sweep of delays from about the end of the interpreter's own start-up (where a Ctrl-C is
Python's, not the package's: a traceback there never passes through the package)."""
import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT

CHECK = [sys.executable, "-m", "pdsketch_mech.check", "domains/basis.pddl", "problems/com.pddl"]

# Runs `check` as `python -m` does, but sends itself SIGINT as the module TARGET starts importing.
TRIP = """
import os, sys  # not signal: the package must not need it before its handler is installed
sys.orig_argv = [sys.executable, "-m", "pdsketch_mech.check"]
class Trip:
    def find_spec(self, name, path=None, target=None):
        if name == {target!r}:
            os.kill(os.getpid(), 2)  # SIGINT
        return None
sys.meta_path.insert(0, Trip())
sys.argv = ["check", "domains/basis.pddl", "problems/com.pddl"]
import runpy
runpy.run_module("pdsketch_mech.check", run_name="__main__", alter_sys=True)
"""


def environment():
    return {**os.environ, "PYTHONPATH": ROOT}


@pytest.mark.parametrize("target", ["signal", "pdsketch_mech.util.process", "typing", "threading", "pdsketch_mech.commands.common"])
def test_ctrl_c_while_the_package_imports_exits_130(target):
    done = subprocess.run([sys.executable, "-c", TRIP.format(target=target)], capture_output=True, text=True,
                          cwd=ROOT, env=environment(), timeout=60)
    assert (done.returncode, done.stderr) == (130, "interrupted\n"), done.stderr[-500:]


def interpreter_start() -> float:
    """Seconds a bare `python -c pass` takes here: the start-up no package code can shorten
    (a Ctrl-C in it is Python's own)."""
    times = []
    for _ in range(3):
        started = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], env=environment(), check=True)
        times.append(time.perf_counter() - started)
    return min(times)


def test_ctrl_c_at_any_early_moment_exits_130_without_a_traceback():
    start = interpreter_start()
    for extra in (0.0, 0.005, 0.01, 0.02, 0.04, 0.08, 0.16, 0.3):
        run = subprocess.Popen(CHECK, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                               env=environment())
        time.sleep(start + extra)
        run.send_signal(signal.SIGINT)
        try:
            _, err = run.communicate(timeout=30)
        finally:
            run.kill()
        if "Traceback" in err:  # still starting (a loaded machine): Python's own, never the package's
            assert "pdsketch_mech" not in err and "KeyboardInterrupt" in err, (extra, err[-800:])
            continue
        assert run.returncode in (130, 0), (extra, run.returncode, err[-500:])  # 0: it finished first
        assert err == ("interrupted\n" if run.returncode == 130 else ""), (extra, err[-500:])
