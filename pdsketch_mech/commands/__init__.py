"""The command-line programs. Each `python -m pdsketch_mech.NAME` is a two-line entry point
(`pdsketch_mech/NAME.py`) that runs `commands/NAME.py`; this package is the top layer and
may import any other."""
