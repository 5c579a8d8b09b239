"""Learning mechanisms: demonstrations are recorded (`recording.py`), segmented by contact
modes and lifted to a mechanism fragment (`extract.py`); self-play labels the generic samplers'
values (`selfplay*.py`); classifiers are trained on them (`sampler_*.py`) and evaluated
(`evaluate.py`). The `learn` command's subcommands live in `*_command.py`."""
