"""Pictures of a world: camera images with PyBullet's TinyRenderer (works headless), PNG
files, and GIFs of executed trajectories."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, List, Sequence, Tuple

import numpy as np
import pybullet as p
from PIL import Image

if TYPE_CHECKING:
    from .world import World


@dataclass(frozen=True)
class Camera:
    """Looks at `target` from `distance` metres at `yaw`/`pitch` degrees."""

    target: Tuple[float, float, float] = (0.4, 0.0, 0.2)
    distance: float = 1.9
    yaw: float = 45.0
    pitch: float = -35.0
    width: int = 480
    height: int = 360
    fov: float = 50.0


def render(world: "World", camera: Camera = Camera()) -> np.ndarray:
    """An RGB image (height, width, 3) of the world as it is now."""
    if not world.visual:
        raise ValueError("this world was built without visual shapes (visual=False): nothing to render")
    view = p.computeViewMatrixFromYawPitchRoll(camera.target, camera.distance, camera.yaw, camera.pitch, 0, 2,
                                               physicsClientId=world.client)
    projection = p.computeProjectionMatrixFOV(camera.fov, camera.width / camera.height, 0.02, 10.0,
                                              physicsClientId=world.client)
    _, _, rgba, _, _ = p.getCameraImage(camera.width, camera.height, view, projection,
                                        renderer=p.ER_TINY_RENDERER, physicsClientId=world.client)
    return np.asarray(rgba, dtype=np.uint8).reshape(camera.height, camera.width, 4)[:, :, :3]


def save_png(image: np.ndarray, path: str) -> None:
    Image.fromarray(image).save(path)


def save_gif(frames: Sequence[np.ndarray], path: str, fps: float = 12.0) -> None:
    """Write frames as a looping GIF."""
    if not frames:
        raise ValueError("no frames to write")
    images: List[Image.Image] = [Image.fromarray(f) for f in frames]
    images[0].save(path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0, optimize=True)
