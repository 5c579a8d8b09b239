"""Helpers shared by the command-line entry points (`python -m pdsketch_mech.X`).

The contract: exit 0 solved or valid, 1 no plan (or the goal is false on replay), 2 bad
input of any kind, 130 interrupted. Bad input is one line on stderr — `FILE:LINE:COL:
error: ...` when it comes from a file, `error: ...` otherwise — and every argument and
output path is checked before any work starts.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from typing import Any, Callable, Dict, List, NoReturn, Optional, Sequence

from ..lang.errors import PddlError, PddlWarning, escape
from ..util import process
from ..util.files import write_json

EXIT_OK, EXIT_UNSOLVED, EXIT_BAD_INPUT = 0, 1, 2
MAX_SEED = 2 ** 32 - 1  # the motion planner's generator takes 32-bit seeds


def print_error(error: PddlError) -> None:
    """The one-line `FILE:LINE:COL: error: ...` on stderr; on a terminal also the source line."""
    source = None
    if sys.stderr.isatty() and error.loc is not None:
        try:
            with open(error.loc.file, encoding="utf-8") as handle:
                source = handle.read()
        except (OSError, UnicodeDecodeError):
            source = None
    print(error.render(source), file=sys.stderr)


def fail(message: str, status: int = EXIT_BAD_INPUT) -> int:
    """Say `error: message` on stderr (one line) and give the exit status to return."""
    print(escape(f"error: {message}"), file=sys.stderr)
    return status


def shown_path(path: str) -> str:
    """`path` as a message shows it: relative to the working folder when it is inside it."""
    relative = os.path.relpath(path)
    return os.path.abspath(path) if relative.startswith("..") else relative


def print_warning(warning: PddlWarning) -> None:
    """The one-line `FILE:LINE:COL: warning: ...` on stderr."""
    print(warning, file=sys.stderr)


def run(main: Callable[[], int]) -> int:
    """Run a command's `main`, turning a closed pipe (`| head`) or Ctrl-C into a quiet exit."""
    try:
        with process.main_running():
            return main()
    except BrokenPipeError:
        _silence_stdout()
        return EXIT_OK
    except KeyboardInterrupt:
        return process.report_interrupt()
    except MemoryError:  # a limit on the process's memory (ulimit -v) was reached: say so in one line
        return fail("out of memory; see docs/limits.md (--max-ground lowers what plan and check accept)")
    except BaseException:
        # After a Ctrl-C, any exception is its consequence: a library that swallowed the
        # KeyboardInterrupt may fail next (trimesh: TypeError on a half-imported module).
        if process.interrupted():
            return process.report_interrupt()
        raise


def run_and_exit(main: Callable[[], int]) -> NoReturn:
    """`run(main)`, then end the process at once with its status. Outputs are complete and
    flushed by then; skipping the interpreter's teardown (unloading scipy, trimesh and
    PyBullet takes 0.15-0.3 s) makes a command end when its time limit says."""
    status = run(main)
    # The one part of the teardown that matters: multiprocessing's exit handler stops pools
    # and unregisters their semaphores, which the resource tracker would otherwise report as
    # leaked under a Ctrl-C's "interrupted" (`learn selfplay --workers K`).
    spawned = sys.modules.get("multiprocessing.util")
    if spawned is not None:
        if process.interrupted():
            process.kill_children()   # so that stopping the pool takes no longer than GRACE
        spawned._exit_function()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except BrokenPipeError:
            _silence_stdout()
    os._exit(status)


def _silence_stdout() -> None:
    # A reader that went away (`| head`): later flushes would fail again; point at /dev/null.
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


# ----------------------------------------------------------------------------- arguments
class ArgumentParser(argparse.ArgumentParser):
    """argparse, but a bad command line is one `error: ...` line and exit 2 (no usage block)."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, escape(f"error: {message}") + "\n")


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def _integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None


def seconds(text: str) -> float:
    """A time limit: a finite number of seconds > 0."""
    value = _number(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive, finite number of seconds, got {text!r}")
    return value


def seed(text: str) -> int:
    """A random seed: a whole number in [0, 2^32 - 1]."""
    value = _integer(text)
    if not 0 <= value <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"must be a whole number from 0 to {MAX_SEED}, got {text!r}")
    return value


def whole(text: str) -> int:
    """A whole number >= 0."""
    value = _integer(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 0, got {text!r}")
    return value


def count(text: str) -> int:
    """How many of something: a whole number >= 1."""
    value = _integer(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1, got {text!r}")
    return value


def number_in(low: float, high: float = math.inf) -> Callable[[str], float]:
    """A finite number in [low, high]."""
    def parse(text: str) -> float:
        value = _number(text)
        if not (math.isfinite(value) and low <= value <= high):
            wanted = f">= {low:g}" if high == math.inf else f"from {low:g} to {high:g}"
            raise argparse.ArgumentTypeError(f"must be a finite number {wanted}, got {text!r}")
        return value
    return parse


def max_ground_option(parser: argparse.ArgumentParser) -> None:
    """`--max-ground N` of check and plan: the grounding size a problem may reach (docs/limits.md)."""
    from ..symbolic.ground_size import DEFAULT_MAX_GROUND, short_number
    parser.add_argument("--max-ground", type=number_in(1.0), default=float(DEFAULT_MAX_GROUND), metavar="N",
                        help="refuse a problem whose grounding is estimated above N atoms, stream instances or "
                             f"macros for one action, stream or mechanism (default {short_number(DEFAULT_MAX_GROUND)})")


def finite(text: str) -> float:
    """Any finite number."""
    value = _number(text)
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def camera_options(parser: argparse.ArgumentParser) -> None:
    """`--yaw`, `--pitch`, `--distance`: where `render`, `plan --render` and `replay --render`
    look from; the camera frames the scene's objects (world/render.py `scene_camera`)."""
    parser.add_argument("--yaw", type=finite, default=45.0, metavar="DEG", help="camera yaw in degrees (default 45)")
    parser.add_argument("--pitch", type=finite, default=-35.0, metavar="DEG",
                        help="camera pitch in degrees (default -35)")
    parser.add_argument("--distance", type=number_in(0.05, 100.0), metavar="M",
                        help="camera distance in metres (default: as close as shows the scene's objects)")


def camera_view(args: argparse.Namespace):
    """The `View` of `camera_options`' values (world/render.py; imported here, not above:
    a classical plan never loads the simulator)."""
    from ..world.render import View
    return View(args.yaw, args.pitch, args.distance)


# ----------------------------------------------------------------------------- output files
def output_error(path: Optional[str], option: str, inputs: Sequence[str] = (),
                 suffixes: Sequence[str] = ()) -> Optional[PddlError]:
    """Why `path` (the value of `option`) cannot be written, or None: its folder must exist,
    it must not be a folder, nor one of the `inputs` (nor the same file under another name),
    and its name must end in one of `suffixes` when they are given."""
    if path is None:
        return None
    folder = os.path.dirname(os.path.abspath(path))
    if suffixes and not path.lower().endswith(tuple(suffixes)):
        return PddlError(f"{option} {path}: the file name must end in {' or '.join(suffixes)}")
    if not os.path.isdir(folder):
        return PddlError(f"{option} {path}: folder {os.path.dirname(path) or '.'} does not exist")
    if os.path.isdir(path):
        return PddlError(f"{option} {path}: is a folder")
    if not os.access(folder, os.W_OK):
        return PddlError(f"{option} {path}: folder {os.path.dirname(path) or '.'} is not writable")
    for source in inputs:
        if _same_file(path, source):
            return PddlError(f"{option} {path}: would overwrite the input file {source}")
    return None


def output_folder(path: str, option: str) -> Optional[str]:
    """Create the folder `path` (the value of `option`), with its parents, if it is missing;
    why it cannot be written to, or None. Options that name a folder create it; options that
    name a file need an existing folder (`output_error`), so that a typo in a folder's name
    is not silently made."""
    if os.path.exists(path) and not os.path.isdir(path):
        return f"{option} {path}: is not a folder"
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as exc:
        return f"{option} {path}: cannot create: {exc.strerror or exc}"
    if not os.access(path, os.W_OK):
        return f"{option} {path}: is not writable"
    return None


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet)
        return os.path.realpath(a) == os.path.realpath(b)


def write_plan_json(path: str, status: str, reason: str, time_s: float, seed: int,
                    plan: List[Dict[str, Any]], stats: Dict[str, Any], problem: str) -> None:
    """Write the `plan --json` document (planner/plan_document.py) atomically."""
    from ..planner.plan_document import plan_document   # here: a command's start-up needs none of it
    write_json(path, plan_document(status, reason, time_s, seed, plan, stats, problem))


def folder_ok(path: Optional[str]) -> bool:
    """Whether the folder `path` would be written into exists (None: nothing to write)."""
    return path is None or os.path.isdir(os.path.dirname(os.path.abspath(path)))


def existing_recording(base: str) -> Optional[str]:
    """Why recording to `base` would replace a recording (without --force), or None."""
    from ..world.recording import recording_paths

    for path in recording_paths(base):
        if os.path.exists(path):
            return f"{shown_path(path)} exists (use --force to replace it)"
    return None
