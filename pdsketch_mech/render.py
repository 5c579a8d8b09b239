"""`python -m pdsketch_mech.render`: the entry point of `commands/render.py`."""
if __name__ == "__main__":
    from .commands.common import run_and_exit
    from .commands.render import main
    run_and_exit(main)
