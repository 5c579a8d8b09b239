"""`python -m pdsketch_mech.replay`: the entry point of `commands/replay.py`."""
if __name__ == "__main__":
    from .commands.common import run_and_exit
    from .commands.replay import main
    run_and_exit(main)
