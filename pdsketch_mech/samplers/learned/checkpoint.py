"""Checkpoints of learned samplers: weights in safetensors, metadata in JSON beside them.

    domains/mechanisms/hook-use.samplers.safetensors   the classifiers' tensors (no code)
    domains/mechanisms/hook-use.samplers.json          what they are and where they came from

Loading never executes code: safetensors holds tensors only, and the JSON is data. The
metadata names the mechanism and a hash of its definition (parameters, precondition,
certified facts, steps; not comments, not the `:sampler` line that points here), so a
checkpoint trained for another version of the mechanism is refused with a message naming
both files.
"""
from __future__ import annotations

import hashlib
import json
import os
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Dict, List, Tuple

import numpy as np

from ...lang.nodes import Mechanism
from ...lang.writer import write_mechanism
from .forward import NumpyClassifiers
from .specs import EncoderConfig, ParamSpec

if TYPE_CHECKING:
    from .model import MechanismClassifiers

SCHEMA = "pdsketch_mech.samplers/2"   # /2: classifiers of proposals (two logits)
READABLE = ("pdsketch_mech.samplers/1", SCHEMA)  # /1: classifiers of verified values
SUFFIX = ".samplers.safetensors"


class CheckpointError(ValueError):
    """A checkpoint that cannot be used (missing, unreadable, for another mechanism)."""


def mechanism_hash(mechanism: Mechanism) -> str:
    """sha256 of the mechanism as written, without its `:sampler` and source location."""
    return hashlib.sha256(write_mechanism(replace(mechanism, sampler=None)).encode()).hexdigest()


def metadata_path(weights: str) -> str:
    base = weights[:-len(".safetensors")] if weights.endswith(".safetensors") else weights
    return base + ".json"


def save(weights: str, model: "MechanismClassifiers", mechanism: Mechanism, info: Dict[str, Any]) -> Tuple[str, str]:
    """Write the weights and the metadata (each atomically); returns both paths."""
    from safetensors.torch import save as to_bytes

    from ...cli import atomic_file, write_json
    tensors = {k: v.detach().contiguous() for k, v in model.state_dict().items()}
    with atomic_file(weights, binary=True, suffix=".safetensors") as handle:
        handle.write(to_bytes(tensors))
    meta = {"schema": SCHEMA, "mechanism": mechanism.name, "mechanism_hash": mechanism_hash(mechanism),
            "encoder": model.encoder.to_json(), "parameters": [s.to_json() for s in model.specs.values()],
            **info}
    write_json(metadata_path(weights), meta)
    return weights, metadata_path(weights)


def read(weights: str, mechanism: Mechanism, fragment: str) -> Tuple[Dict[str, np.ndarray], Dict[str, Any]]:
    """The tensors (as numpy arrays) and metadata of `mechanism`'s checkpoint (defined in
    `fragment`); CheckpointError if the files are missing or unreadable or were trained for
    another definition. Imports no torch. The metadata gains `weights_sha256`, the weights
    file's digest (what is derived from the weights is cached on disk under it)."""
    from safetensors import SafetensorError
    from safetensors.numpy import load as load_bytes
    meta_file = metadata_path(weights)
    for path in (weights, meta_file):
        if not os.path.isfile(path):
            raise CheckpointError(f"{path}: not found (the checkpoint of mechanism '{mechanism.name}' in {fragment})")
    try:
        with open(meta_file, encoding="utf-8") as handle:
            meta = json.load(handle)
        if meta.get("schema") not in READABLE:
            raise CheckpointError(f"{meta_file}: not a learned-sampler checkpoint ({SCHEMA})")
        if meta.get("mechanism") != mechanism.name or meta.get("mechanism_hash") != mechanism_hash(mechanism):
            raise CheckpointError(
                f"{weights} was trained for another definition of mechanism '{meta.get('mechanism')}' than the one "
                f"in {fragment}; retrain it (python -m pdsketch_mech.learn train {mechanism.name} --fragment {fragment} "
                f"--force) or plan with "
                "--no-learned-samplers")
        layout(meta)
        with open(weights, "rb") as handle:
            data = handle.read()
        tensors = load_bytes(data)
        meta["weights_sha256"] = hashlib.sha256(data).hexdigest()
    except (OSError, ValueError, KeyError, TypeError, SafetensorError) as exc:
        if isinstance(exc, CheckpointError):
            raise
        raise CheckpointError(f"{weights}: cannot load the checkpoint: {str(exc).splitlines()[0]}") from None
    return tensors, meta


def layout(meta: Dict[str, Any]) -> Tuple[List[ParamSpec], EncoderConfig]:
    """The classifiers' specs and encoder a checkpoint's metadata describes."""
    return [ParamSpec.from_json(s) for s in meta["parameters"]], EncoderConfig.from_json(meta["encoder"])


def load(weights: str, mechanism: Mechanism, fragment: str) -> Tuple["MechanismClassifiers", Dict[str, Any]]:
    """The torch classifiers of `mechanism` from `weights` (see `read`)."""
    import torch

    from .model import MechanismClassifiers
    tensors, meta = read(weights, mechanism, fragment)
    model = MechanismClassifiers(*layout(meta))
    try:
        model.load_state_dict({k: torch.from_numpy(v) for k, v in tensors.items()}, strict=True)
    except RuntimeError as exc:
        raise CheckpointError(f"{weights}: cannot load the checkpoint: {str(exc).splitlines()[0]}") from None
    model.eval()
    return model, meta


def load_numpy(weights: str, mechanism: Mechanism, fragment: str) -> Tuple[NumpyClassifiers, Dict[str, Any]]:
    """The classifiers of `mechanism` from `weights` for numpy's forward pass (planning)."""
    tensors, meta = read(weights, mechanism, fragment)
    classifiers = NumpyClassifiers(*layout(meta), tensors)
    try:
        classifiers.check()
    except (KeyError, ValueError) as exc:
        raise CheckpointError(f"{weights}: cannot load the checkpoint: its tensors do not fit the classifiers "
                              f"its metadata describes ({type(exc).__name__}: {exc})") from None
    return classifiers, meta


def context_count(meta: Dict[str, Any]) -> int:
    """How many context objects (context.py) the checkpoint's self-play recorded per episode
    beside the mechanism's own: its classifiers read as many (0 for checkpoints before them)."""
    return int(meta.get("selfplay", {}).get("context", 0))
