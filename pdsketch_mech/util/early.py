"""The first code a command runs (`pdsketch_mech/__init__` imports it before anything else):
from here until `process.install_interrupt_handler`, Ctrl-C ends the process at once with
`interrupted` and status 130. Importing `process` (typing, re, enum, threading) takes about
10 ms, in which Python's default handler printed a traceback. Only modules the interpreter
has already loaded, or built in, are used here: sys, os and _signal (the `signal` module
imports enum, which takes milliseconds), and no `from __future__` import: the __future__
module is not loaded at start-up, and importing it is a window of its own."""
import _signal
import os
import sys

EXIT_INTERRUPTED = 130
SCRIPT_PREFIX = "pdsketch-"


def _exit_now(signum, frame) -> None:
    os.write(2, b"interrupted\n")
    os._exit(EXIT_INTERRUPTED)




def command_module(argv: "list[str] | tuple[str, ...]") -> "str | None":
    """The module run by `python [options] -m MODULE ...` (`sys.orig_argv`), else None."""
    args = iter(argv[1:])
    for arg in args:
        if arg == "-m":
            return next(args, None)
        if arg.startswith("-m"):
            return arg[2:]
        if arg in ("-X", "-W"):
            next(args, None)
        elif arg == "-c" or not arg.startswith("-"):
            script = os.path.basename(arg)   # a console script pip installed (`pdsketch-plan`) is one of ours
            return "pdsketch_mech." + script[len(SCRIPT_PREFIX):] if script.startswith(SCRIPT_PREFIX) else None
    return None


def is_command() -> bool:
    """Whether this process runs one of the package's commands (`python -m pdsketch_mech.X`)."""
    module = command_module(getattr(sys, "orig_argv", ()))
    return module is not None and module.split(".")[0] == __name__.split(".")[0]


def install(previous: object = None) -> None:
    """In a command, Ctrl-C exits 130 at once (nothing is held before `main` runs). The
    package's `__init__` sets such a handler as its first statement, for any importer (each
    bytecode before it is a moment where Python's own handler prints a traceback); in any
    other importer, `previous`, the handler it had, is put back."""
    if is_command():
        _signal.signal(_signal.SIGINT, _exit_now)
    elif previous is not None:
        _signal.signal(_signal.SIGINT, previous)
