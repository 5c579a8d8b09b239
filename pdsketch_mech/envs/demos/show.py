"""Pictures of a recording: replay the recorded joint and object poses in a world built from
the recording's own problem text (no physics), render frames to a GIF, and a strip of key
frames with the contact points drawn on them."""
from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np
import pybullet as p
from PIL import Image, ImageDraw

from ...lang.parser import parse_text
from ...world.build import build_world
from ...world.recording import Recording
from ...world.render import Camera, render, save_gif
from ...world.world import World

CONTACT_DISTANCE = 2e-3   # drawn contacts: closer than this (PyBullet also reports near misses)
ROBOT_COLOR = (220, 30, 30)     # robot-object contacts
OBJECT_COLOR = (30, 90, 230)    # object-object contacts (an object and the table included)


def camera_for(recording: Recording, width: int = 480, height: int = 360) -> Camera:
    """A camera looking at where the objects are (the middle of their recorded positions)."""
    poses = recording.arrays["poses"]
    movable = [i for i, b in enumerate(recording.header["bodies"][1:]) if b["kind"] == "movable"]
    if movable:
        xyz = poses[:, movable, :3].reshape(-1, 3)
        target = tuple(float(v) for v in (np.clip(xyz.mean(axis=0), (0.3, -0.4, 0.0), (0.9, 0.4, 0.3))))
    else:
        target = (0.55, 0.0, 0.05)
    return Camera(target=(target[0], target[1], 0.1), distance=1.15, yaw=62.0, pitch=-30.0,
                  width=width, height=height)


def replay_world(recording: Recording) -> World:
    problem = parse_text(recording.header["problem"], file=recording.header.get("problem_file", "<recording>"))
    return build_world(problem)


def set_frame(world: World, recording: Recording, frame: int) -> None:
    """Put the arm, the fingers and every object where they were at `frame`."""
    a = recording.arrays
    world.set_arm(a["joints"][frame])
    for joint, value in zip((9, 10), a["fingers"][frame]):
        p.resetJointState(world.robot, joint, float(value), physicsClientId=world.client)
    for name, pose in zip(recording.objects, a["poses"][frame]):
        if not world.bodies[name].fixed:
            world.set_pose(name, (tuple(pose[:3]), tuple(pose[3:])))


def _project(camera: Camera, world: World, points: np.ndarray) -> np.ndarray:
    view = np.array(p.computeViewMatrixFromYawPitchRoll(camera.target, camera.distance, camera.yaw, camera.pitch, 0, 2,
                                                         physicsClientId=world.client)).reshape(4, 4).T
    proj = np.array(p.computeProjectionMatrixFOV(camera.fov, camera.width / camera.height, 0.02, 10.0,
                                                 physicsClientId=world.client)).reshape(4, 4).T
    homo = np.hstack([points, np.ones((len(points), 1))])
    clip = (proj @ view @ homo.T).T
    ndc = clip[:, :3] / clip[:, 3:4]
    return np.stack([(ndc[:, 0] + 1) / 2 * camera.width, (1 - ndc[:, 1]) / 2 * camera.height], axis=1)


def draw_contacts(image: np.ndarray, world: World, camera: Camera, recording: Recording, frame: int) -> Image.Image:
    """The frame's image with its contact points as dots (red: the robot, blue: between objects)."""
    out = Image.fromarray(image)
    rows = recording.contacts(frame)
    near = rows["distance"] < CONTACT_DISTANCE
    if not near.any():
        return out
    bodies = rows["bodies"][near]
    points = rows["position_b"][near].astype(float)
    pixels = _project(camera, world, points)
    draw = ImageDraw.Draw(out)
    for (a, b), (u, v) in zip(bodies, pixels):
        if a == b == 0:
            continue  # the robot's own links
        color = ROBOT_COLOR if 0 in (a, b) else OBJECT_COLOR
        draw.ellipse((u - 3, v - 3, u + 3, v + 3), fill=color, outline=(255, 255, 255))
    return out


def contact_signature(recording: Recording, frame: int) -> Tuple:
    """Which pairs of bodies touch at `frame` (the robot as 0), plus the gripper's state."""
    rows = recording.contacts(frame)
    pairs = {tuple(sorted((int(a), int(b)))) for (a, b), d in zip(rows["bodies"], rows["distance"])
             if d < CONTACT_DISTANCE and not (a == b == 0)}
    robot = frozenset(x for pair in pairs if 0 in pair for x in pair if x != 0)
    return robot, frozenset(pair for pair in pairs if 0 not in pair)


def key_frames(recording: Recording, count: int = 6, min_phase: int = 12) -> List[int]:
    """`count` frames for a strip: the first, the last, and the middle of every phase in
    which the robot touches the same objects for at least `min_phase` frames (0.2 s),
    spread evenly if there are more."""
    n = recording.frames
    signatures = [contact_signature(recording, frame)[0] for frame in range(n)]
    phases, start = [], 0
    for frame in range(1, n + 1):
        if frame == n or signatures[frame] != signatures[start]:
            if frame - start >= min_phase:
                phases.append((start, frame - 1))
            start = frame
    candidates = sorted({0, n - 1} | {(a + b) // 2 for a, b in phases})
    if len(candidates) > count:
        picks = np.linspace(0, len(candidates) - 1, count).round().astype(int)
        candidates = [candidates[i] for i in sorted(set(picks))]
    return candidates


def render_gif(recording: Recording, path: str, every: int = 8, fps: float = 15.0,
               camera: Optional[Camera] = None) -> int:
    camera = camera or camera_for(recording)
    frames = list(range(0, recording.frames, every))
    if frames[-1] != recording.frames - 1:
        frames.append(recording.frames - 1)
    images = []
    with replay_world(recording) as world:
        for frame in frames:
            set_frame(world, recording, frame)
            images.append(render(world, camera))
    save_gif(images, path, fps=fps)
    return len(images)


def render_strip(recording: Recording, path: str, frames: Optional[Sequence[int]] = None, columns: int = 3,
                 camera: Optional[Camera] = None) -> List[int]:
    camera = camera or camera_for(recording, 400, 300)
    frames = list(frames) if frames is not None else key_frames(recording)
    tiles = []
    with replay_world(recording) as world:
        for frame in frames:
            set_frame(world, recording, frame)
            tile = draw_contacts(render(world, camera), world, camera, recording, frame)
            ImageDraw.Draw(tile).text((6, 4), f"t = {recording.arrays['time'][frame]:.1f} s", fill=(0, 0, 0))
            tiles.append(tile)
    rows = (len(tiles) + columns - 1) // columns
    w, h = tiles[0].size
    sheet = Image.new("RGB", (w * min(columns, len(tiles)), h * rows), "white")
    for k, tile in enumerate(tiles):
        sheet.paste(tile, ((k % columns) * w, (k // columns) * h))
    sheet.save(path, optimize=True)
    return frames
