"""Compiles the default placement's kernels (and, by making its room's capture, the import's) before anything is timed.

numba compiles each loop on its first call in a checkout and caches the machine code (core/cache.py); a placement that
runs first in a fresh checkout would otherwise count ~10 s of compilation as its own time (`make demo` on a fresh clone:
the default's selection 11.8 s, 0.3 s on the second run). `compile_placement_kernels` places probes in a small
synthetic room with the default, leak-aware through the room's own walls (leaks.md: the remembered segments' loops
too), and projects points onto a hull larger than the room's placement reaches, which calls every kernel the default
calls with the same argument types (tests/quality/test_quality_warmup.py lists any it misses on a level), and returns
the seconds it took (near 0 once cached). Beside it, on the other core, a partner process compiles the kernels it reaches
last into numba's disk cache (warmup_partner.py; the cache's entries kept whole by core/cache_guard.py): in an empty
cache the warm-up took 42.0 s alone and 27.8 s so. A finished warm-up leaves a marker in numba's cache folder
(`warm_up_marker`), so that `lpnn place` warms up once per checkout before its first default placement instead of
compiling inside it.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from ...core.analytic_scene import AnalyticScene
from ...core.capture import Capture
from ...core.cache import NUMBA_CACHE_ENV, project_cache_dir, use_project_cache_for_numba
from ...core.cache_guard import can_guard
from ...core.grid import EvaluationGrid
from ...scenes.raycast_kernel import bad_rays
from ..metric.hull_projection import project_to_hull
from ..metric.metric import ReferenceField
from ..metric.triangulation import tetrahedralize
from .refined_insertion import refined_insertion

WARM_UP_TOLERANCE = 0.05
WARM_UP_CELL = 0.5  # ~1,000 points: large enough that point location walks instead of testing every tetrahedron
WARM_UP_HULL_PROBES = 200  # a random cloud's hull: 82 triangles, more than SMALL_HULL_FACES (32)
WARM_UP_OUTSIDE_POINTS = 400  # x 82 triangles: ~33,000 pairs, more than WHOLE_SEARCH_PAIRS (16,384)
PARTNER_COMMAND = (sys.executable, "-m", "lpnn.quality.placement.warmup_partner")
PARTNER_STOP_SECONDS = 5.0  # how long a stopped partner may take to exit before it is killed
MARKER_FOLDER = "lpnn-warm-ups"  # in numba's cache folder: one empty file per warmed-up state of the sources
PACKAGE = Path(__file__).resolve().parents[2]  # lpnn/


def compile_placement_kernels(partner: Sequence[str] | None = PARTNER_COMMAND) -> float:
    """Runs the default placement once on a synthetic room; the seconds it took. `partner`: the command of the process
    compiling the late kernels beside it (module text; None: none)."""
    start = time.perf_counter()
    with partner_process(partner):
        scene, capture, field = warm_up_room()
        refined_insertion(field, EvaluationGrid(cell_size=capture.cell_size, ids=capture.ids),
                          tolerance=WARM_UP_TOLERANCE, leaks=scene.raycaster)
        # The room's raycaster is analytic: the Embree raycaster's ray check, which a level's leak checks call, apart.
        bad_rays(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]))
        project_outside_a_hull()
    _leave(warm_up_marker())
    return time.perf_counter() - start


def warm_up_room() -> tuple[AnalyticScene, Capture, ReferenceField]:
    """The synthetic room the warm-up and its partner place in (the same one: the same kernel argument types)."""
    scene = AnalyticScene.random(1, cell_size=WARM_UP_CELL)
    capture = scene.capture(name="warm-up")
    return scene, capture, ReferenceField.from_capture(capture)


def warm_up_marker(package: Path = PACKAGE) -> Path:
    """The marker a finished warm-up leaves (compile_placement_kernels), named by the sources the warm-up compiled
    (every module of `package`: its path, size and modification time), numba's and Python's versions and the host's
    CPU. numba's own cache keys a kernel on its source's contents and the CPU, so the marker is stricter (a file only
    touched renames it too): any source edited, another checkout, another numba or machine: another name, no marker."""
    use_project_cache_for_numba()  # before numba is imported (core/cache.py)
    import llvmlite.binding
    import numba

    machine = f"{llvmlite.binding.get_process_triple()} {llvmlite.binding.get_host_cpu_name()}"
    digest = hashlib.sha256(f"{numba.__version__}\n{sys.version}\n{machine}\n{package}\n".encode())
    for source in sorted(package.rglob("*.py")):
        stat = source.stat()
        digest.update(f"{source.relative_to(package).as_posix()} {stat.st_size} {stat.st_mtime_ns}\n".encode())
    folder = Path(os.environ.get(NUMBA_CACHE_ENV) or project_cache_dir() / "numba")
    return folder / MARKER_FOLDER / digest.hexdigest()[:32]


def kernels_warm(package: Path = PACKAGE) -> bool:
    """Whether a warm-up finished for these sources (warm_up_marker): their kernels are in numba's disk cache."""
    return warm_up_marker(package).is_file()


def _leave(marker: Path) -> None:
    """Writes the empty marker by rename, so that a reader never sees half of it; a cache folder it cannot write to
    (numba then caches elsewhere or not at all) leaves none, and the next `lpnn place` warms up again."""
    try:
        marker.parent.mkdir(parents=True, exist_ok=True)
        partial = marker.with_name(f"{marker.name}.{os.getpid()}.tmp")
        partial.write_bytes(b"")
        os.replace(partial, marker)
    except OSError:
        pass


@contextmanager
def partner_process(command: Sequence[str] | None) -> Iterator[subprocess.Popen | None]:
    """`command` running beside the block (its output discarded; this package on its PYTHONPATH), stopped when the
    block ends: by then the warm-up has called every kernel itself, so whatever the partner is still compiling is not
    needed, and a partner that failed cost nothing but its core. The partner also stops when its stdin closes, so it
    never outlives this process. None (no process) without a command, on a single core (the two would share it),
    where the cache's files cannot be locked (core/cache_guard.py) or the process cannot start."""
    if command is None or (os.cpu_count() or 1) < 2 or not can_guard():
        yield None
        return
    path = os.environ.get("PYTHONPATH")
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join([str(PACKAGE.parent)] + ([path] if path else [])))
    try:
        process = subprocess.Popen(list(command), stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL, env=environment)
    except OSError:  # e.g. no process can be started here: the warm-up alone
        process = None
    if process is None:
        yield None
        return
    try:
        yield process
    finally:
        process.stdin.close()
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=PARTNER_STOP_SECONDS)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def project_outside_a_hull() -> None:
    """Point location's projection onto a hull of more than SMALL_HULL_FACES triangles for more than WHOLE_SEARCH_PAIRS
    pairs (the centroid tree, the certificate and the tie rule's loops), which the room's small placement never
    reaches but a level's points outside the probes' hull do (hull_projection.py)."""
    rng = np.random.default_rng(0)
    mesh = tetrahedralize(rng.uniform(-1.0, 1.0, (WARM_UP_HULL_PROBES, 3)))
    directions = rng.normal(size=(WARM_UP_OUTSIDE_POINTS, 3))
    outside = 3.0 * directions / np.linalg.norm(directions, axis=1, keepdims=True)
    project_to_hull(mesh.points, mesh.hull_faces, outside, owners=mesh.hull_face_tets)
