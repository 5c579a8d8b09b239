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
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Tuple

import numpy as np

from ...lang.errors import PddlError
from ...lang.nodes import Loc, Mechanism
from .definition import definition_text, mechanism_hash, serves
from .forward import NumpyClassifiers
from .specs import EncoderConfig, ParamSpec

if TYPE_CHECKING:
    from .model import MechanismClassifiers

SCHEMA = "pdsketch_mech.samplers/2"   # /2: classifiers of proposals (two logits)
READABLE = ("pdsketch_mech.samplers/1", SCHEMA)  # /1: classifiers of verified values
SUFFIX = ".samplers.safetensors"


class CheckpointError(ValueError):
    """A checkpoint that cannot be used (missing, unreadable, for another mechanism); `loc`
    is the place in the metadata file when the JSON itself is broken."""

    def __init__(self, message: str, loc: Optional[Loc] = None):
        super().__init__(f"{loc}: {message}" if loc is not None else message)
        self.message, self.loc = message, loc

    def as_pddl_error(self) -> PddlError:
        """The same report as the commands print bad input: `FILE:LINE:COL: error: ...` or `error: ...`."""
        return PddlError(self.message, self.loc)


def metadata_path(weights: str) -> str:
    base = weights[:-len(".safetensors")] if weights.endswith(".safetensors") else weights
    return base + ".json"


def save(weights: str, model: "MechanismClassifiers", mechanism: Mechanism, info: Dict[str, Any]) -> Tuple[str, str]:
    """Write the weights and the metadata (each atomically); returns both paths."""
    from safetensors.torch import save as to_bytes

    from ...util.files import atomic_file, write_json
    tensors = {k: v.detach().contiguous() for k, v in model.state_dict().items()}
    with atomic_file(weights, binary=True, suffix=".safetensors") as handle:
        handle.write(to_bytes(tensors))
    meta = {"schema": SCHEMA, "mechanism": mechanism.name, "mechanism_hash": mechanism_hash(mechanism),
            "definition": definition_text(mechanism),
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
    meta = read_metadata(meta_file)
    if meta.get("mechanism") != mechanism.name:
        raise CheckpointError(
            f"{weights} was trained for mechanism '{meta.get('mechanism')}', not '{mechanism.name}' (in {fragment}); "
            f"train one for it (python -m pdsketch_mech.learn train {mechanism.name} --fragment {fragment}) or "
            "plan with --no-learned-samplers")
    named = {s.get("variable") for s in meta.get("parameters", []) if isinstance(s, dict)}
    if not serves(meta.get("definition"), meta.get("mechanism_hash"), mechanism, named):
        raise CheckpointError(
            f"{weights} was trained for another definition of mechanism '{mechanism.name}' than the one "
            f"in {fragment}; retrain it (python -m pdsketch_mech.learn train {mechanism.name} --fragment {fragment} "
            f"--force) or plan with "
            "--no-learned-samplers")
    try:
        with open(weights, "rb") as handle:
            data = handle.read()
        tensors = load_bytes(data)
    except (OSError, ValueError, SafetensorError) as exc:
        raise CheckpointError(f"{weights}: cannot load the checkpoint: {str(exc).splitlines()[0]}") from None
    meta["weights_sha256"] = hashlib.sha256(data).hexdigest()
    return tensors, meta


def read_metadata(meta_file: str) -> Dict[str, Any]:
    """A checkpoint's metadata, checked to describe classifiers (CheckpointError naming the
    JSON file, and the place in it when the JSON is broken, otherwise)."""
    try:
        with open(meta_file, encoding="utf-8") as handle:
            meta = json.load(handle)
    except json.JSONDecodeError as exc:
        raise CheckpointError(f"the checkpoint's metadata is not valid JSON: {exc.msg}",
                              Loc(meta_file, exc.lineno, exc.colno)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise CheckpointError(f"{meta_file}: cannot read the checkpoint's metadata: {exc}") from None
    if not isinstance(meta, dict) or meta.get("schema") not in READABLE:
        raise CheckpointError(f"{meta_file}: not a learned-sampler checkpoint ({SCHEMA})")
    try:
        if not isinstance(meta["mechanism"], str):
            raise TypeError("'mechanism' is not a name")
        layout(meta)
        context_count(meta)
    except (KeyError, ValueError, TypeError, AttributeError) as exc:
        raise CheckpointError(f"{meta_file}: the checkpoint's metadata is malformed "
                              f"({type(exc).__name__}: {exc})") from None
    return meta


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
