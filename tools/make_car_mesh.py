#!/usr/bin/env python3
"""Generates the car of materials/scenes/cache-car.json: three OBJ meshes beside the scene.

    PYTHONPATH=python .venv/bin/python tools/make_car_mesh.py [--check]

cache-car-body.obj     the lower body (bonnet, flanks, boot) and the roof: the car paint;
cache-car-windows.obj  the band of the cabin below the roof: dark glass;
cache-car-wheels.obj   four tyres with their hubs.

A simple, recognisable saloon 4.3 m long, 1.76 m wide and 1.38 m high, its length along x
(the bonnet towards +x), resting on y = 0. Every part is a stack of closed rings (rounded
rectangles, circles) joined by quads and closed by fans to a centre point, so every mesh is
closed and smooth: the renderer smooths a file's normals over shared vertices
(patina.geometry.shapes.from_file), and a rounded stack has no crease for it to smear.
The body's top follows a height profile that falls towards the nose (the bonnet), the
cabin's rings shrink with height, faster at the front (the raked windscreen) than at the
back. 5,632 triangles, 160 kB of text. Same bytes on every run; `--check` compares.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "materials", "scenes")
RING_POINTS = 64  # around a body or cabin ring: the flanks' highlights stay smooth at 384 wide
WHEEL_POINTS = 40  # around a tyre
HALF_LENGTH, HALF_WIDTH = 2.15, 0.88  # the lower body, m
SILL, BELT = 0.28, 0.86  # the body's bottom and its top at the back (the beltline), m
BONNET_DROP = 0.14  # how much lower the body's top is at the nose than at the beltline, m
SQUARENESS = 6.0  # superellipse exponent of the rings: 2 an ellipse, large a rectangle
ROOF, WINDOWS_TOP = 1.38, 0.8  # the cabin's top, m; the windows' share of the cabin's height
WHEEL_RADIUS, TYRE_WIDTH, AXLE_X = 0.33, 0.22, 1.32
WHEEL_Z = HALF_WIDTH - 0.08  # the tyre's middle: it stands out of the flank by 0.03 m


def superellipse(half_x: float, half_z: float, points: int = RING_POINTS) -> np.ndarray:
    """(points, 2) x, z on |x / half_x|^n + |z / half_z|^n = 1, counter-clockwise seen from +y."""
    angle = np.linspace(0.0, 2.0 * np.pi, points, endpoint=False)
    c, s = np.cos(angle), np.sin(angle)
    power = 2.0 / SQUARENESS
    return np.stack([half_x * np.sign(c) * np.abs(c) ** power, half_z * np.sign(s) * np.abs(s) ** power], axis=1)


def rounded(level: np.ndarray) -> np.ndarray:
    """The inset (0 to 1) of a ring at level 0..1 of a stack with rounded bottom and top edges:
    a quarter circle over the first and last fifth of the height."""
    edge = np.clip(np.minimum(level, 1.0 - level) / 0.2, 0.0, 1.0)
    return 1.0 - np.sqrt(1.0 - (1.0 - edge) ** 2)


def lower_body_rings() -> list[np.ndarray]:
    """The lower body: rings from the sill to the top, each (points, 3); the top falls towards
    the nose by BONNET_DROP (smoothly over the front half), so the front reads as a bonnet."""
    rings = []
    for level in np.linspace(0.0, 1.0, 13):
        inset = 0.12 * rounded(level)
        xz = superellipse(HALF_LENGTH - inset, HALF_WIDTH - inset)
        front = np.clip(xz[:, 0] / HALF_LENGTH, 0.0, 1.0) ** 2
        top = BELT - BONNET_DROP * front
        y = SILL + level * (top - SILL)
        rings.append(np.stack([xz[:, 0], y, xz[:, 1]], axis=1))
    return rings


def cabin_rings(levels: np.ndarray) -> list[np.ndarray]:
    """The cabin from the beltline to the roof at `levels` (0..1): its front edge moves back
    1.0 m (the windscreen), its rear edge forward 0.55 m (the rear window), its sides in
    0.16 m (the tumblehome); the last 20 % rounds over into the roof."""
    rings = []
    for level in levels:
        lean = level + 0.35 * rounded(np.asarray(max(level, 0.5)))  # the roof's edge rounds over
        front, rear = 1.05 - 1.0 * lean, -1.55 + 0.55 * lean
        xz = superellipse((front - rear) / 2, HALF_WIDTH - 0.06 - 0.16 * lean)
        y = BELT - 0.02 + level * (ROOF - BELT + 0.02)
        rings.append(np.stack([xz[:, 0] + (front + rear) / 2, np.full(len(xz), y), xz[:, 1]], axis=1))
    return rings


def tyre_rings(axle_x: float, side: float) -> list[np.ndarray]:
    """A tyre on the axle at x = axle_x, on the side z = side x WHEEL_Z: circles about the
    axle along a rounded profile (hub face, shoulder, tread, shoulder, hub face)."""
    profile = [(0.55, -0.5), (0.8, -0.5), (0.95, -0.45), (1.0, -0.3), (1.0, 0.3), (0.95, 0.45), (0.8, 0.5), (0.55, 0.5)]
    angle = np.linspace(0.0, 2.0 * np.pi, WHEEL_POINTS, endpoint=False)
    rings = []
    for radius, across in profile:
        r = radius * WHEEL_RADIUS
        z = side * (WHEEL_Z + across * TYRE_WIDTH)
        x, y = axle_x + r * np.cos(angle), WHEEL_RADIUS + r * np.sin(angle)
        rings.append(np.stack([x, y, np.full_like(angle, z)], axis=1))
    return rings[::-1] if side > 0 else rings  # outward winding on both sides


def stack_triangles(rings: list[np.ndarray], close_start: bool, close_end: bool) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and triangles of rings joined in order by quads, closed by a fan to each end
    ring's centre where asked. Triangles wind counter-clockwise seen from outside when the
    rings run counter-clockwise seen from the end the stack runs towards."""
    points = len(rings[0])
    vertices = list(rings)
    triangles = []
    nxt = (np.arange(points) + 1) % points
    for k in range(len(rings) - 1):
        a, b = k * points + np.arange(points), (k + 1) * points + np.arange(points)
        a1, b1 = k * points + nxt, (k + 1) * points + nxt
        triangles += [np.stack([a, b1, a1], 1), np.stack([a, b, b1], 1)]
    for closes, ring_index, flip in ((close_start, 0, False), (close_end, len(rings) - 1, True)):
        if closes:
            centre = sum(len(v) for v in vertices)
            vertices.append(rings[ring_index].mean(axis=0, keepdims=True))
            ring = ring_index * points + np.arange(points)
            fan = np.stack([np.full(points, centre), ring, ring[nxt]], 1)
            triangles.append(fan[:, [0, 2, 1]] if flip else fan)
    return np.concatenate(vertices), np.concatenate(triangles)


def joined(parts: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """One mesh of several parts: the vertex arrays end to end, each part's indices moved on."""
    vertices, triangles, base = [], [], 0
    for v, t in parts:
        vertices.append(v)
        triangles.append(t + base)
        base += len(v)
    return np.concatenate(vertices), np.concatenate(triangles)


def car_meshes() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The three files' meshes by file name."""
    split = round(WINDOWS_TOP * 10)  # the ring where the windows end, of the cabin's 11
    levels = np.linspace(0.0, 1.0, 11)
    body = stack_triangles(lower_body_rings(), close_start=True, close_end=True)
    roof = stack_triangles(cabin_rings(levels[split:]), close_start=False, close_end=True)
    windows = stack_triangles(cabin_rings(levels[: split + 1]), close_start=True, close_end=False)
    wheels = [
        stack_triangles(tyre_rings(x, side), close_start=True, close_end=True)
        for x in (AXLE_X, -AXLE_X - 0.05)
        for side in (1.0, -1.0)
    ]
    return {
        "cache-car-body.obj": joined([body, roof]),
        "cache-car-windows.obj": windows,
        "cache-car-wheels.obj": joined(wheels),
    }


def obj_text(name: str, vertices: np.ndarray, triangles: np.ndarray) -> str:
    header = [
        f"# {name}: part of the car of cache-car.json, written by tools/make_car_mesh.py (run it to",
        "# regenerate; --check compares). Generated geometry, no third-party content; licence: as Patina.",
        f"# {len(vertices)} vertices, {len(triangles)} triangles, metres, y up, the car's nose towards +x.",
    ]
    lines = header + [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the bundled files instead of writing")
    args = parser.parse_args()
    stale = []
    for name, (vertices, triangles) in car_meshes().items():
        path = os.path.join(SCENES, name)
        text = obj_text(name, vertices, triangles)
        if args.check:
            with open(path, encoding="utf-8") as f:
                if f.read() != text:
                    stale.append(name)
        else:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        print(f"{name}: {len(vertices)} vertices, {len(triangles)} triangles")
    if stale:
        print(f"make_car_mesh.py: differs from the bundled file: {', '.join(stale)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
