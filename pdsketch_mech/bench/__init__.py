"""Benchmarks: `python -m pdsketch_mech.bench ipc DIR` times our classical planner on IPC
problems, optionally side by side with pyperplan (a benchmark-only dependency)."""
