"""Pictures of a world: camera images with PyBullet's TinyRenderer (works headless), PNG
files, and GIFs of executed trajectories. `scene_camera` frames a scene's objects: the
commands' pictures use it, seen from a `View` (yaw, pitch, and a distance or none)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, List, Optional, Sequence, Tuple

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


@dataclass(frozen=True)
class View:
    """Where a framing camera looks from: yaw and pitch in degrees, and the distance in
    metres (None: as close as frames the scene)."""

    yaw: float = 45.0
    pitch: float = -35.0
    distance: Optional[float] = None


FRAMED_SIZE = (640, 480)   # pixels of a framed picture
HEADROOM = 0.25            # metres above the objects kept in view: where the hand lifts what it holds
FRAME_MARGIN = 1.15        # the framed region's bounding sphere fills the view's height less this
DISTANCES = (0.5, 4.0)     # metres a framing camera stays within


def movable_boxes(world: "World") -> List[Tuple[np.ndarray, np.ndarray]]:
    """The world AABBs of the movable objects where they are now."""
    return [world.aabb(name) for name in world.movable()]


def scene_camera(world: "World", view: View = View(), size: Tuple[int, int] = FRAMED_SIZE,
                 boxes: Optional[Sequence[Tuple[np.ndarray, np.ndarray]]] = None) -> Camera:
    """A camera on the region the plan acts in: the bounding box of the movable objects
    (where they are now, or `boxes`: everywhere they went), with HEADROOM above them, and the
    robot's shoulder, where its reach starts (so that the arm is seen coming in), from
    `view`'s yaw and pitch, as close as shows all of it (or at `view.distance`). A scene
    without movable objects gets the default target."""
    boxes = movable_boxes(world) if boxes is None else list(boxes)
    if boxes:
        lo = np.min([b[0] for b in boxes] + [world.shoulder], axis=0)
        hi = np.max([b[1] + (0.0, 0.0, HEADROOM) for b in boxes] + [world.shoulder], axis=0)
        target = tuple(float(v) for v in (lo + hi) / 2)
        radius = float(np.linalg.norm(hi - lo)) / 2
    else:
        target, radius = Camera.target, Camera.distance * math.sin(math.radians(Camera.fov / 2))
    fitting = radius / math.sin(math.radians(Camera.fov / 2)) * FRAME_MARGIN
    distance = view.distance if view.distance is not None else min(max(fitting, DISTANCES[0]), DISTANCES[1])
    return Camera(target=target, distance=distance, yaw=view.yaw, pitch=view.pitch, width=size[0], height=size[1])


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
