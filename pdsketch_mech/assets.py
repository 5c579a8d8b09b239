"""`python -m pdsketch_mech.assets`: the entry point of `commands/assets.py`."""
if __name__ == "__main__":
    from .commands.assets import main
    from .commands.common import run_and_exit
    run_and_exit(main)
