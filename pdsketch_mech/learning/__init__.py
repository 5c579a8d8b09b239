"""Learning mechanisms: recorded demonstrations (`world/recording.py`) are segmented by contact
modes and lifted to a mechanism fragment (`extract.py`); self-play labels the generic samplers'
values (`selfplay*.py`); classifiers are trained on them (`sampler_*.py`) and evaluated
(`evaluate.py`). The `learn` command is `commands/learn*.py`."""
