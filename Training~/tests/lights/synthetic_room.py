"""An analytic scene for the light-rig tests: a closed box room (inward-facing walls split into a
regular grid of triangles) with an optional solid pillar, lit by known point lights through our own
forward model. Independent of any BSP: the target is built straight from geometry, so the tests
check the model and the optimiser against lights we chose, not against lightmaps we also wrote.
"""

from __future__ import annotations

import numpy as np

from lpnn.lights.model import ForwardModel, Lights
from lpnn.lights.target import RadianceTarget
from lpnn.scenes.raycast import EmbreeRaycaster
from lpnn.scenes.surfaces import triangle_areas

ROOM_SIDE = 256.0  # Quake units (6.5 m)


def box_walls(mins: np.ndarray, maxs: np.ndarray, divisions: int, inward: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices (V, 3), normals (V, 3) and triangles (T, 3) of an axis-aligned box's six sides, each
    a divisions x divisions grid; normals point into the box (a room) or out of it (a pillar)."""
    vertices, normals, triangles = [], [], []
    t = np.linspace(0.0, 1.0, divisions + 1)
    u, v = np.meshgrid(t, t, indexing="ij")
    cells = np.array([(i * (divisions + 1) + j, (i + 1) * (divisions + 1) + j, (i + 1) * (divisions + 1) + j + 1,
                       i * (divisions + 1) + j + 1) for i in range(divisions) for j in range(divisions)])
    for axis in range(3):
        a, b = (axis + 1) % 3, (axis + 2) % 3
        for side, value in ((-1.0, mins[axis]), (1.0, maxs[axis])):
            points = np.zeros((u.size, 3))
            points[:, axis] = value
            points[:, a] = mins[a] + u.ravel() * (maxs[a] - mins[a])
            points[:, b] = mins[b] + v.ravel() * (maxs[b] - mins[b])
            normal = np.zeros(3)
            normal[axis] = -side if inward else side
            base = sum(len(p) for p in vertices)
            vertices.append(points)
            normals.append(np.tile(normal, (len(points), 1)))
            triangles.append(np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]]) + base)
    return np.concatenate(vertices), np.concatenate(normals), np.concatenate(triangles)


def room_geometry(divisions: int = 8, pillar: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    vertices, normals, triangles = box_walls(np.zeros(3), np.full(3, ROOM_SIDE), divisions, inward=True)
    if pillar:
        pv, pn, pt = box_walls(np.array([112.0, 112.0, 0.0]), np.array([144.0, 144.0, 160.0]), 2, inward=False)
        vertices, normals = np.concatenate([vertices, pv]), np.concatenate([normals, pn])
        triangles = np.concatenate([triangles, pt + len(vertices) - len(pv)])
    return vertices, normals, triangles


def room_target(vertices: np.ndarray, normals: np.ndarray, triangles: np.ndarray, radiance: np.ndarray,
                albedo: np.ndarray) -> RadianceTarget:
    areas = np.bincount(triangles.ravel(), weights=np.repeat(triangle_areas(vertices, triangles) / 3, 3),
                        minlength=len(vertices))
    return RadianceTarget(positions=vertices, normals=normals, areas=areas, radiance=radiance, albedo=albedo,
                          projection_loss=0.0, samples_per_triangle=1)


def wall_albedo(vertices: np.ndarray) -> np.ndarray:
    """A different, smoothly varying colour over the room so colour and position are both identifiable."""
    return 0.35 + 0.3 * np.stack([vertices[:, 0], vertices[:, 1], vertices[:, 2]], axis=1) / ROOM_SIDE


def lit_room(lights: Lights, divisions: int = 8, pillar: bool = True) -> tuple[ForwardModel, EmbreeRaycaster]:
    """The forward model of the room whose target is the radiance of `lights` (shadow rays included)."""
    vertices, normals, triangles = room_geometry(divisions, pillar)
    albedo = wall_albedo(vertices)
    raycaster = EmbreeRaycaster(vertices, triangles, threads=1)
    blank = room_target(vertices, normals, triangles, np.zeros_like(vertices), albedo)
    render = ForwardModel(blank, raycaster)
    radiance = render.radiance_of(lights, render.visibility(lights))
    return ForwardModel(room_target(vertices, normals, triangles, radiance, albedo), raycaster), raycaster


def inside_room(points: np.ndarray, pillar: bool = True) -> np.ndarray:
    """The open-space test of the room: inside the walls and outside the pillar."""
    inside = np.all((points > 0) & (points < ROOM_SIDE), axis=1)
    if pillar:
        inside &= ~np.all((points > [112, 112, 0]) & (points < [144, 144, 160]), axis=1)
    return inside


TRUE_LIGHTS = Lights(positions=np.array([[64.0, 64.0, 200.0], [200.0, 180.0, 96.0]]),
                     colours=np.array([[1.0, 0.8, 0.6], [0.5, 0.7, 1.0]]), intensities=np.array([250.0, 150.0]),
                     ambient=np.array([12.0, 10.0, 8.0]))
