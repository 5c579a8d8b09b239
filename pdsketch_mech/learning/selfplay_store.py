"""Self-play data on disk: one `.npz` per episode, written atomically, and a JSON manifest.

    OUT/manifest.json           the configuration and a summary (rewritten after each episode)
    OUT/episodes/e000012.npz    episode 12's arrays (selfplay.episode_arrays)

An episode's file is written to a temporary name in the same folder and renamed, so a file
that exists is complete: an interrupt (Ctrl-C, kill) loses at most the episodes in flight,
and a rerun skips the episodes whose files exist. The files, not the manifest, say what is
done (a kill between the rename and the manifest's update loses nothing). `load_dataset`
concatenates the episodes in episode order.
"""
from __future__ import annotations

import glob
import json
import os
import re
from typing import Dict, Iterable, List, Optional, Sequence

import numpy as np

from ..util.files import atomic_file, write_json

SCHEMA = "pdsketch_mech.selfplay/2"  # /2: rejected proposals logged too
EPISODE_FILE = re.compile(r"^e(\d{6,})\.npz$")


class StoreError(ValueError):
    """The folder cannot take this run's data (another configuration's data, unreadable)."""


def episode_path(folder: str, episode: int) -> str:
    return os.path.join(folder, "episodes", f"e{episode:06d}.npz")


def done_episodes(folder: str) -> List[int]:
    """Episodes whose files exist (complete by construction), sorted."""
    names = (os.path.basename(p) for p in glob.glob(os.path.join(folder, "episodes", "e*.npz")))
    return sorted(int(m.group(1)) for m in map(EPISODE_FILE.match, names) if m)


def write_episode(folder: str, arrays: Dict[str, np.ndarray]) -> str:
    """Write one episode's arrays atomically (temporary file + rename)."""
    path = episode_path(folder, int(arrays["episode_id"][0]))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with atomic_file(path, binary=True, suffix=".npz") as handle:
        np.savez_compressed(handle, **arrays)
        handle.flush()
        os.fsync(handle.fileno())
    return path


def read_episode(folder: str, episode: int) -> Dict[str, np.ndarray]:
    with np.load(episode_path(folder, episode), allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def read_manifest(folder: str) -> Optional[Dict[str, object]]:
    """The manifest of `folder` (None if it has none), its configuration's split "train",
    grounding "any" and context 0 when the folder predates them; StoreError if it cannot be read or is not self-play's."""
    path = os.path.join(folder, "manifest.json")
    if not os.path.exists(path):
        return None
    try:
        with open(path, encoding="utf-8") as handle:
            manifest = json.load(handle)
    except (OSError, ValueError) as exc:
        raise StoreError(f"{path}: cannot read the manifest: {exc}") from None
    if not isinstance(manifest, dict) or manifest.get("schema") != SCHEMA:
        found = manifest.get("schema") if isinstance(manifest, dict) else None
        raise StoreError(f"{path}: self-play data of another format ({found}, this version writes {SCHEMA}); "
                         "use another --out" if isinstance(found, str) and found.startswith("pdsketch_mech.selfplay/")
                         else f"{path}: not a self-play manifest ({SCHEMA})")
    # Folders older than these options were made the one way there was then.
    manifest["config"] = {"split": "train", "grounding": "any", "context": 0, **manifest.get("config", {})}
    return manifest


def check_definition(folder: str, theirs: Dict[str, object], digest: object, fragment: str) -> None:
    """StoreError if the data were played with another definition of the mechanism than
    `digest` (`mechanism_hash` of the one in `fragment`). Folders made before the hash was
    recorded have none: they are not checked."""
    if theirs.get("mechanism_hash") not in (None, digest):
        raise StoreError(f"{folder} holds self-play episodes of another definition of mechanism "
                         f"{theirs.get('mechanism')} than the one in {fragment}; use a new --out, or delete "
                         "the folder to play them again")


def open_folder(folder: str, identity: Dict[str, object], fragment: str = "the fragment") -> Dict[str, object]:
    """The manifest of `folder` for a run of `identity` (a new one if there is none);
    StoreError if the folder holds another configuration's data, or data of another
    definition of the mechanism (`identity`'s mechanism_hash) than the one in `fragment`."""
    manifest = read_manifest(folder)
    if manifest is not None:
        theirs = manifest["config"]
        check_definition(folder, theirs, identity.get("mechanism_hash"), fragment)
        if theirs.get("mechanism_hash") is None and not done_episodes(folder):
            theirs["mechanism_hash"] = identity.get("mechanism_hash")  # no episode yet: record it from now on
        differs = [f"{k} {theirs.get(k)!r} (this run: {v!r})" for k, v in identity.items()
                   if theirs.get(k) != v and k != "mechanism_hash"]
        if differs:
            raise StoreError(f"{folder} holds self-play data of another configuration: " + ", ".join(differs)
                             + "; use another --out or the same options")
        return manifest
    if done_episodes(folder):
        raise StoreError(f"{folder} holds episode files but no manifest.json; use another --out")
    return {"schema": SCHEMA, "config": dict(identity)}


def update_manifest(folder: str, manifest: Dict[str, object], summaries: Iterable[Dict[str, object]],
                    command: Optional[str] = None) -> None:
    """Rewrite the manifest (atomically) with the episodes' summaries, in episode order."""
    rows = {int(r["episode"]): r for r in manifest.get("episodes", [])}
    rows.update({int(r["episode"]): r for r in summaries})
    manifest["episodes"] = [rows[k] for k in sorted(rows)]
    manifest["totals"] = totals(manifest["episodes"])
    if command:
        manifest["command"] = command
    os.makedirs(folder, exist_ok=True)
    write_json(os.path.join(folder, "manifest.json"), manifest)


def totals(rows: Sequence[Dict[str, object]]) -> Dict[str, int]:
    """The manifest's totals over its episode rows."""
    return {"episodes": len(rows), "successes": sum(bool(r["success"]) for r in rows),
            "samples": sum(int(r["samples"]) for r in rows), "positives": sum(int(r["positives"]) for r in rows),
            "timed_out": sum(bool(r.get("timed_out")) for r in rows)}


def first_episodes(manifest: Dict[str, object], count: int) -> Dict[str, object]:
    """A copy of the manifest that keeps episodes 0..count-1 only (what `train --episodes
    count` trains on), its totals theirs."""
    rows = [r for r in manifest.get("episodes", []) if int(r["episode"]) < count]
    return {**manifest, "episodes": rows, "totals": totals(rows)}


def summary(arrays: Dict[str, np.ndarray]) -> Dict[str, object]:
    """One manifest row for an episode."""
    return {"episode": int(arrays["episode_id"][0]), "instance_seed": int(arrays["episode_instance_seed"][0]),
            "success": bool(arrays["episode_success"][0]), "objects": [str(o) for o in arrays["episode_objects"][0]],
            "samples": int(len(arrays["label"])), "positives": int(arrays["label"].sum()),
            "units": int(arrays["episode_units"][0]), "timed_out": bool(arrays["episode_timed_out"][0]),
            "seconds": round(float(arrays["episode_seconds"][0]), 3)}


def load_dataset(folder: str, episodes: Optional[Iterable[int]] = None) -> Dict[str, np.ndarray]:
    """The episodes' arrays concatenated in episode order; `parents` become row indices
    into the concatenated sample arrays (-1: none)."""
    chosen = sorted(episodes) if episodes is not None else done_episodes(folder)
    parts = [read_episode(folder, e) for e in chosen]
    if not parts:
        raise StoreError(f"{folder}: no self-play episodes")
    offset = 0
    for part in parts:
        parents = part["parents"]
        part["parents"] = np.where(parents >= 0, parents + offset, -1)
        offset += len(part["label"])
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
