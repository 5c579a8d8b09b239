"""Running self-play episodes, in this process or in K worker processes, into a folder.

Workers are started with `spawn` (a fresh interpreter: no PyBullet client or OMPL state is
inherited from a fork) and are sent the picklable `SelfPlayConfig` and episode ids; each
builds its own worlds. Results come back as arrays and this process writes them, one file
per episode, so what is on disk never depends on which worker ran what: episode i's data
are a function of (config, i) alone, for K = 1 and K = 2 alike.

With the Ray backend (`--backend ray`, the optional `ray` extra) episodes are Ray tasks
instead: `ray.init(num_cpus=K)` starts a local instance, or joins the cluster that
`RAY_ADDRESS` names; the results are the same arrays, written the same way.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time
from typing import Callable, Dict, Iterator, List, Optional, Sequence

import numpy as np

from ..util.ray_tasks import ray_unordered
from .selfplay import SelfPlayConfig, run_episode
from .selfplay_store import done_episodes, open_folder, summary, update_manifest, write_episode

# Called with each finished episode's summary row (the progress bar).
Progress = Callable[[Dict[str, object]], None]


def _init_worker(parent: int) -> None:
    # Ctrl-C goes to the whole process group: the parent stops the pool; workers printing
    # their own KeyboardInterrupt tracebacks would only bury the one-line message.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # A parent killed outright (SIGKILL) cannot stop its pool: workers would run on as
    # orphans, burning the CPU for results nobody reads. They watch for it and quit.
    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)
    threading.Thread(target=watch, daemon=True).start()


def _terminate(signum, frame) -> None:
    # `kill` (SIGTERM) ends the run like Ctrl-C: the pool's exit stops the workers.
    raise KeyboardInterrupt


def _work(job) -> Dict[str, np.ndarray]:
    config, episode = job
    return run_episode(config, episode)


def _results(config: SelfPlayConfig, todo: Sequence[int], workers: int,
             backend: str = "local") -> Iterator[Dict[str, np.ndarray]]:
    if backend == "ray":
        # Set-iteration order must not depend on a worker's hash seed.
        yield from ray_unordered(_work, [(config, e) for e in todo], workers, {"PYTHONHASHSEED": "0"})
        return
    if workers <= 1 or len(todo) <= 1:
        for episode in todo:
            yield run_episode(config, episode)
        return
    # Set-iteration order must not depend on a worker's hash seed.
    os.environ.setdefault("PYTHONHASHSEED", "0")
    context = multiprocessing.get_context("spawn")
    previous = signal.signal(signal.SIGTERM, _terminate) if threading.current_thread() is threading.main_thread() \
        else None
    try:
        with context.Pool(min(workers, len(todo)), initializer=_init_worker, initargs=(os.getpid(),)) as pool:
            # chunksize 1: a long episode does not hold back others queued behind it in a batch.
            yield from pool.imap_unordered(_work, [(config, e) for e in todo], chunksize=1)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def pending(folder: str, episodes: int) -> List[int]:
    """Episodes 0..episodes-1 whose files do not exist yet."""
    done = set(done_episodes(folder))
    return [e for e in range(episodes) if e not in done]


def run_selfplay(config: SelfPlayConfig, folder: str, episodes: int, workers: int = 1,
                 progress: Optional[Progress] = None, command: Optional[str] = None,
                 backend: str = "local") -> Dict[str, object]:
    """Run the episodes of 0..episodes-1 not on disk yet; returns the manifest. Each finished
    episode is written (atomically) and recorded in the manifest before the next is awaited."""
    manifest = open_folder(folder, config.identity(), config.fragment)
    os.makedirs(folder, exist_ok=True)
    todo = pending(folder, episodes)
    update_manifest(folder, manifest, [], command)
    for arrays in _results(config, todo, workers, backend):
        write_episode(folder, arrays)
        row = summary(arrays)
        update_manifest(folder, manifest, [row], command)
        if progress is not None:
            progress(row)
    return manifest
