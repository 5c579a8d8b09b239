"""Helpers below every other layer: the process (start time, Ctrl-C), the on-disk cache,
atomic file writes, progress bars, and Ray. Nothing here imports the rest of the package."""
