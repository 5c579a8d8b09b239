"""Learning mechanisms from demonstrations: recordings (`recording.py`); extraction,
self-play and sampler training arrive with their issues."""
