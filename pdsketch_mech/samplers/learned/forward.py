"""The classifiers' forward pass in numpy: what planning runs, so that it never imports torch.

Importing torch costs 1.4-2.8 s on this machine, more than a whole Center-of-Mass plan with
learned samplers spends ranking. The network is small (a PointNet++ encoder run once per shape,
then MLPs over batches of 16 proposals), so numpy runs it in a few milliseconds. The weights
are the checkpoint's tensors under the names torch gave them (model.py, pointnet.py define
the layout); tests check that both passes give the same scores.
"""
from __future__ import annotations

from typing import Dict, List, Mapping, Sequence, Tuple

import numpy as np

from .specs import MIN_HALF_EXTENT, POSE, SIZE, EncoderConfig, ParamSpec, framed_columns, scaled_columns, width

Tensors = Mapping[str, np.ndarray]
LAYER_NORM_EPS = 1e-5  # torch.nn.LayerNorm's default


def relu(x: np.ndarray) -> np.ndarray:
    return np.maximum(x, 0.0)


def log_sigmoid(x: np.ndarray) -> np.ndarray:
    return -np.logaddexp(0.0, -x)


class Layers:
    """Named layers of a checkpoint (torch's state-dict names, e.g. `by_variable.g1.head.0`)."""

    def __init__(self, tensors: Tensors, prefix: str):
        self.tensors, self.prefix = tensors, prefix

    def __getitem__(self, name: str) -> np.ndarray:
        return self.tensors[f"{self.prefix}.{name}"]

    def linear(self, name: str, x: np.ndarray) -> np.ndarray:
        return x @ self[f"{name}.weight"].T + self[f"{name}.bias"]

    def layer_norm(self, name: str, x: np.ndarray) -> np.ndarray:
        mean = x.mean(-1, keepdims=True)
        var = ((x - mean) ** 2).mean(-1, keepdims=True)
        return (x - mean) / np.sqrt(var + LAYER_NORM_EPS) * self[f"{name}.weight"] + self[f"{name}.bias"]

    def shared_mlp(self, name: str, x: np.ndarray, layers: int) -> np.ndarray:
        """pointnet.shared_mlp: (Linear, LayerNorm, ReLU) x layers."""
        for i in range(layers):
            x = relu(self.layer_norm(f"{name}.{3 * i + 1}", self.linear(f"{name}.{3 * i}", x)))
        return x

    def mlp(self, name: str, x: np.ndarray) -> np.ndarray:
        """model.mlp: Linear, ReLU, Linear, ReLU."""
        return relu(self.linear(f"{name}.2", relu(self.linear(f"{name}.0", x))))

    def standardise(self, name: str, x: np.ndarray) -> np.ndarray:
        return (x - self[f"{name}.mean"]) / self[f"{name}.std"]


def farthest_points(xyz: np.ndarray, count: int) -> np.ndarray:
    """Indices (count,) of farthest-point samples of a cloud (N, 3), from point 0 (as pointnet.py)."""
    chosen = np.zeros(count, dtype=np.int64)
    distance = np.full(len(xyz), np.inf)
    farthest = 0
    for i in range(count):
        chosen[i] = farthest
        distance = np.minimum(distance, ((xyz - xyz[farthest]) ** 2).sum(-1))
        farthest = int(distance.argmax())
    return chosen


def ball_query(xyz: np.ndarray, centres: np.ndarray, radius: float, k: int) -> np.ndarray:
    """Indices (M, k) of up to k points within `radius` of each centre, nearest first, the
    nearest filling in when fewer fall inside (as pointnet.py)."""
    d2 = ((centres[:, None, :] - xyz[None, :, :]) ** 2).sum(-1)
    k = min(k, len(xyz))
    near = np.argsort(d2, axis=-1, kind="stable")[:, :k]
    outside = np.take_along_axis(d2, near, -1) > radius * radius
    return np.where(outside, near[:, :1], near)


def groupings(cloud: np.ndarray, encoder: EncoderConfig) -> List[Tuple[np.ndarray, np.ndarray]]:
    """Per set-abstraction level, the neighbours' indices (M, k) and the centres (M, 3): they
    depend on the cloud and the encoder's layout only, not on weights, so a shape read by
    several classifiers (one per parameter) is grouped once (most of an embedding's time)."""
    key = (cloud.shape, cloud.dtype.str, cloud.tobytes(), encoder.centres, encoder.radii, encoder.neighbours)
    if key not in _GROUPINGS:
        if len(_GROUPINGS) >= 64:
            del _GROUPINGS[next(iter(_GROUPINGS))]
        xyz, levels = cloud.astype(np.float64), []
        for centres, radius in zip(encoder.centres, encoder.radii):
            centre = xyz[farthest_points(xyz, min(centres, len(xyz)))]
            levels.append((ball_query(xyz, centre, radius, encoder.neighbours), centre))
            xyz = centre
        _GROUPINGS[key] = levels
    return _GROUPINGS[key]


_GROUPINGS: Dict[tuple, List[Tuple[np.ndarray, np.ndarray]]] = {}


class NumpyClassifier:
    """One parameter's classifier (model.ParamClassifier) as numpy arrays."""

    def __init__(self, spec: ParamSpec, encoder: EncoderConfig, tensors: Tensors):
        self.spec, self.encoder = spec, encoder
        self.layers = Layers(tensors, f"by_variable.{spec.variable.lstrip('?')}")

    def shape_vector(self, cloud: np.ndarray) -> np.ndarray:
        """(SHAPE_PROJECTION,) embedding of one unit cloud (N, 3)."""
        layers, features = self.layers, None
        levels = groupings(cloud, self.encoder)
        for level, (group, centre) in enumerate(levels):
            xyz = levels[level - 1][1] if level else cloud.astype(np.float64)
            local = xyz[group] - centre[:, None, :]
            if features is not None:
                local = np.concatenate([local, features[group]], -1)
            widths = (self.encoder.widths1, self.encoder.widths2)[level]
            features = layers.shared_mlp(f"shape.sa{level + 1}.mlp", local, len(widths)).max(axis=1)
        pooled = layers.shared_mlp("shape.glob", np.concatenate([levels[-1][1], features], -1), 1).max(axis=0)
        return layers.linear("shape_projection", pooled)

    def log_score(self, value: np.ndarray, parents: Sequence[np.ndarray], present: np.ndarray,
                  sizes: np.ndarray, poses: np.ndarray, shapes: np.ndarray) -> np.ndarray:
        """(B,) `ParamClassifier.log_score` of B values (B, width) in one context: parents (one
        (width,) row each, zeros when absent), present (P,), sizes (M, 3), poses (M, 7),
        shapes (M, SHAPE_PROJECTION)."""
        layers, rows = self.layers, len(value)
        parts: List[np.ndarray] = []
        for m in range(self.spec.objects):
            inputs = [np.broadcast_to(poses[m], (rows, POSE)), np.broadcast_to(sizes[m], (rows, SIZE))]
            framed = {}
            for start, stop, is_point in framed_columns(self.spec):
                columns = value[:, start:stop] - poses[m, :3] if is_point else value[:, start:stop]
                framed[start, stop] = rotate_inverse(poses[m, 3:], columns)
                inputs.append(framed[start, stop])
            for start, stop, is_framed in scaled_columns(self.spec):
                columns = framed[start, stop] if is_framed else value[:, start:stop]
                inputs.append(columns / np.maximum(sizes[m], MIN_HALF_EXTENT))
            features = layers.standardise(f"object_norm.{m}", np.concatenate(inputs, -1))
            parts.append(layers.mlp(f"objects.{m}", np.concatenate([np.broadcast_to(shapes[m], (rows, len(shapes[m]))),
                                                                    features], -1)))
        for p in range(len(self.spec.parents)):
            row = np.concatenate([layers.standardise(f"parent_norm.{p}", parents[p]) * present[p], present[p:p + 1]])
            embedded = layers.mlp(f"parents.{p}", row)
            parts.append(np.broadcast_to(embedded, (rows, len(embedded))))
        parts.append(layers.mlp("value", layers.standardise("value_norm", value)))
        logits = layers.linear("head.2", relu(layers.linear("head.0", np.concatenate(parts, -1))))
        if self.spec.outputs == 1:
            return logits[:, 0]
        return log_sigmoid(logits - layers["prior_shift"]).sum(-1)

    def position_statistics(self, slot: int) -> Tuple[np.ndarray, np.ndarray]:
        """Mean and standard deviation of object `slot`'s x and y over the training rows (the
        first columns of its input standardisation: its pose comes first)."""
        return self.layers[f"object_norm.{slot}.mean"][:2], self.layers[f"object_norm.{slot}.std"][:2]


def rotate_inverse(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate vectors v (..., 3) by the inverse of the unit quaternion q (x, y, z, w)."""
    u, w = -q[:3], q[3]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


class NumpyClassifiers:
    """A mechanism's classifiers by variable (model.MechanismClassifiers without torch)."""

    def __init__(self, specs: Sequence[ParamSpec], encoder: EncoderConfig, tensors: Tensors):
        arrays = {k: np.asarray(v, dtype=np.float64) for k, v in tensors.items()}
        self.by_variable: Dict[str, NumpyClassifier] = {
            s.variable.lstrip("?"): NumpyClassifier(s, encoder, arrays) for s in specs}

    def classifier(self, variable: str) -> NumpyClassifier:
        return self.by_variable[variable.lstrip("?")]

    def check(self) -> None:
        """Run every classifier once on zeros: KeyError or ValueError if the tensors do not
        make the network the specs describe (a load must fail now, not in the middle of a plan)."""
        for classifier in self.by_variable.values():
            spec = classifier.spec
            shape = classifier.shape_vector(np.zeros((8, 3)))
            classifier.log_score(np.zeros((2, width(spec.kind))), [np.zeros(width(k)) for _, k in spec.parents],
                                 np.zeros(len(spec.parents)), np.ones((spec.objects, 3)),
                                 np.tile([0.0, 0, 0, 0, 0, 0, 1], (spec.objects, 1)),
                                 np.tile(shape, (spec.objects, 1)))

    def __contains__(self, variable: object) -> bool:
        return isinstance(variable, str) and variable.lstrip("?") in self.by_variable
