"""The console scripts pip installs (`pdsketch-plan`, `pdsketch-check`, ...): the same programs
as `python -m pdsketch_mech.NAME`. `util/early.py` recognises their processes as commands."""
from importlib import import_module
from typing import NoReturn

from .common import run_and_exit


def _run(name: str) -> NoReturn:
    run_and_exit(import_module(f"pdsketch_mech.commands.{name}").main)


def plan() -> NoReturn:
    _run("plan")


def check() -> NoReturn:
    _run("check")


def replay() -> NoReturn:
    _run("replay")


def render() -> NoReturn:
    _run("render")


def learn() -> NoReturn:
    _run("learn")


def demo() -> NoReturn:
    _run("demo")


def envs() -> NoReturn:
    _run("envs")
