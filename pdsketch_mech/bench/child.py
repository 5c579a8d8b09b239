"""Run a function in a forked child under a time and a memory limit, and measure its peak.

The fuzzer checks thousands of files: a fork shares the parent's loaded modules (no start-up
cost), and a file that makes `check` allocate without bound is stopped by the child's own
address-space limit (RLIMIT_AS, set to what the child has mapped plus the allowance) rather
than by the kernel's out-of-memory killer, with the machine's other processes as victims.
"""
from __future__ import annotations

import json
import os
import resource
import select
import signal
import time
from dataclasses import dataclass
import subprocess
from typing import Any, Callable, Optional, Tuple


@dataclass
class ChildResult:
    value: Any                # what the function returned (JSON), None on a hang or a memory error
    hang: bool = False        # killed after `seconds`
    out_of_memory: bool = False  # a MemoryError, or a peak above the allowance
    peak_mb: float = 0.0      # resident memory grown above the parent's at the fork


def _status_kb(field: str) -> int:
    with open("/proc/self/status", encoding="ascii") as handle:
        for line in handle:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return 0


def process_peak_mb(pid: int) -> Optional[float]:
    """The peak resident memory of a running process (VmHWM), or None once it has ended.
    Read while it runs: wait4's maxrss of a process started by fork and exec includes the
    memory of the process it was forked from, which Linux carries across exec."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
    except (OSError, ValueError):
        pass
    return None


def wait_measured(child: "subprocess.Popen", seconds: float) -> Tuple[Optional[int], float, float]:
    """Wait for `child` at most `seconds` (then kill it): its exit status (None if killed),
    wall time since the call and peak resident memory (polled every 10 ms)."""
    started = time.perf_counter()
    peak = 0.0
    while True:
        pid, status, _ = os.wait4(child.pid, os.WNOHANG)
        if pid:
            child.returncode = os.waitstatus_to_exitcode(status)
            return child.returncode, time.perf_counter() - started, peak
        if time.perf_counter() - started > seconds:
            child.kill()
            os.wait4(child.pid, 0)
            child.returncode = -9
            return None, time.perf_counter() - started, peak
        peak = max(peak, process_peak_mb(child.pid) or 0.0)
        time.sleep(0.01)


def run_limited(function: Callable[[], Any], seconds: float, memory_mb: float) -> ChildResult:
    """`function()` in a forked child: killed after `seconds`, its address space limited to
    what it inherits plus `memory_mb`. Its return value must be JSON-serialisable."""
    base_kb = _status_kb("VmRSS")
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: never returns
        os.close(read_fd)
        try:
            limit = (_status_kb("VmSize") + int(memory_mb * 1024)) * 1024
            resource.setrlimit(resource.RLIMIT_AS, (limit, resource.RLIM_INFINITY))
            payload = json.dumps({"value": function()})
        except MemoryError:
            payload = json.dumps({"memory": True})
        except BaseException as exc:  # reported as the value's crash, not lost
            payload = json.dumps({"value": None, "error": f"{type(exc).__name__}: {exc}"[:500]})
        data = payload.encode()
        while data:
            data = data[os.write(write_fd, data):]
        os._exit(0)
    os.close(write_fd)
    chunks, deadline, hang = [], time.monotonic() + seconds, False
    try:
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                hang = True
                break
            ready, _, _ = select.select([read_fd], [], [], remaining)
            if ready:
                chunk = os.read(read_fd, 1 << 16)
                if not chunk:
                    break
                chunks.append(chunk)
    finally:
        os.close(read_fd)
        if hang:
            os.kill(pid, signal.SIGKILL)
        _, status, usage = os.wait4(pid, 0)
    peak_mb = max(0.0, (usage.ru_maxrss - base_kb) / 1024)
    if hang:
        return ChildResult(None, hang=True, peak_mb=peak_mb)
    if not chunks:  # killed, or a native crash; near the limit, a failed allocation in C code
        ended = f"signal {os.WTERMSIG(status)}" if os.WIFSIGNALED(status) else f"exit {os.WEXITSTATUS(status)}"
        return ChildResult({"error": f"the child ended without a reply ({ended})"},
                           out_of_memory=peak_mb > 0.9 * memory_mb, peak_mb=peak_mb)
    reply: dict = json.loads(b"".join(chunks))
    if reply.get("memory") or peak_mb > memory_mb:
        return ChildResult(reply.get("value"), out_of_memory=True, peak_mb=peak_mb)
    if "error" in reply:
        return ChildResult({"error": reply["error"]}, peak_mb=peak_mb)
    return ChildResult(reply["value"], peak_mb=peak_mb)


def child_error(result: ChildResult) -> Optional[str]:
    """The exception that escaped the child's function, if one did."""
    value = result.value
    return value["error"] if isinstance(value, dict) and "error" in value else None
