"""`python -m pdsketch_mech.demo`: the entry point of `commands/demo.py`."""
if __name__ == "__main__":
    import sys

    from .commands.common import run
    from .commands.demo import main
    sys.exit(run(main))
