"""Running a function over many inputs as Ray tasks (the optional `ray` extra): the backend
that `learn selfplay --backend ray` and `bench mechanisms/compose --backend ray` share."""
from __future__ import annotations

import os
from typing import Any, Callable, Dict, Iterable, Iterator, Optional


def ray_unordered(function: Callable[[Any], Any], inputs: Iterable[Any], workers: int,
                  env_vars: Optional[Dict[str, str]] = None) -> Iterator[Any]:
    """function(x) for each input, as each finishes: one CPU per task on a local instance
    of `workers` CPUs, or on the cluster RAY_ADDRESS names (joined, and left as it was)."""
    import ray
    started_here = not ray.is_initialized()
    if started_here:
        ray.init(num_cpus=None if os.environ.get("RAY_ADDRESS") else workers, include_dashboard=False,
                 log_to_driver=False, logging_level="ERROR", configure_logging=False,
                 runtime_env={"env_vars": dict(env_vars or {})})
    try:
        remote = ray.remote(num_cpus=1)(function)
        pending = [remote.remote(x) for x in inputs]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            yield ray.get(done[0])
    finally:
        if started_here:
            ray.shutdown()
