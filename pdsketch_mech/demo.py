"""`python -m pdsketch_mech.demo`: the entry point of `commands/demo.py`."""
if __name__ == "__main__":
    from .commands.common import run_and_exit
    from .commands.demo import main
    run_and_exit(main)
