"""The rays `lpnn place` casts for the leak rule (Embree over the capture's level, lpnn.scenes.capture_geometry), served
over stdin/stdout to the C# Apply benchmark (ApplyBench.cs, --rays embree): the C# leak-aware Apply then gets exactly
Python's segment answers, so its probes can be compared with `lpnn place`'s with the raycaster taken out of the question.
Protocol (little-endian), two requests, each named by its first byte:
  b"C" (cast, IRaycaster.Cast): int32 R, float32 max distance, R x 3 float32 origins, R x 3 float32 unit directions;
       reply R float32 distances (+inf: no hit) and R x 3 float32 normals.
  b"E" (each ray to its own end, IPerRayDistanceRaycaster.Cast: how the segment test casts, as lpnn.core.segments does
       with `first_hit_distances`): int32 R, R float32 max distances, R x 3 float32 origins, R x 3 float32 unit
       directions; reply R float32 distances (+inf: no hit).
Run as: python embree_raycaster_server.py CAPTURE
"""

from __future__ import annotations

import struct
import sys
from typing import BinaryIO

import numpy as np

from lpnn.core.capture_file import read_capture
from lpnn.core.pipe_protocol import read_exactly
from lpnn.scenes.capture_geometry import capture_raycaster

CAST, OWN_ENDS = b"C", b"E"


def read_rays(source: BinaryIO, count: int) -> tuple[np.ndarray, np.ndarray]:
    """origins (R, 3) and directions (R, 3) float64 from their float32s."""
    rays = np.frombuffer(read_exactly(source, 24 * count), dtype="<f4").astype(np.float64)
    return rays[:3 * count].reshape(count, 3), rays[3 * count:].reshape(count, 3)


def main(capture_path: str) -> int:
    raycaster, why = capture_raycaster(read_capture(capture_path))
    if raycaster is None:
        print(f"{capture_path}: {why}", file=sys.stderr)
        return 1
    source, sink = sys.stdin.buffer, sys.stdout.buffer
    while True:
        try:
            kind = read_exactly(source, 1)
        except EOFError:
            return 0
        (count,) = struct.unpack("<i", read_exactly(source, 4))
        if kind == CAST:
            (max_distance,) = struct.unpack("<f", read_exactly(source, 4))
            origins, directions = read_rays(source, count)
            distances, normals = raycaster.cast(origins, directions, float(max_distance))
            sink.write(distances.astype("<f4").tobytes() + normals.astype("<f4").tobytes())
        elif kind == OWN_ENDS:
            ends = np.frombuffer(read_exactly(source, 4 * count), dtype="<f4").astype(np.float64)
            origins, directions = read_rays(source, count)
            sink.write(raycaster.first_hit_distances(origins, directions, ends).astype("<f4").tobytes())
        else:
            print(f"unknown request {kind!r} (expected {CAST!r} or {OWN_ENDS!r})", file=sys.stderr)
            return 2
        sink.flush()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
