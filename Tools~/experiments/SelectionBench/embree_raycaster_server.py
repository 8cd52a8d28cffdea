"""The rays `lpnn place` casts for the leak rule (Embree over the capture's level, lpnn.scenes.capture_geometry), served
over stdin/stdout to the C# Apply benchmark (ApplyBench.cs, --rays embree): the C# leak-aware Apply then gets exactly
Python's segment answers, so its probes can be compared with `lpnn place`'s with the raycaster taken out of the question.
Protocol (little-endian): request int32 R, float32 max distance, R x 3 float32 origins, R x 3 float32 unit directions;
reply R float32 distances (+inf: no hit) and R x 3 float32 normals.
Run as: python embree_raycaster_server.py CAPTURE
"""

from __future__ import annotations

import struct
import sys

import numpy as np

from lpnn.core.capture_file import read_capture
from lpnn.core.pipe_protocol import read_exactly
from lpnn.scenes.capture_geometry import capture_raycaster


def main(capture_path: str) -> int:
    raycaster, why = capture_raycaster(read_capture(capture_path))
    if raycaster is None:
        print(f"{capture_path}: {why}", file=sys.stderr)
        return 1
    source, sink = sys.stdin.buffer, sys.stdout.buffer
    while True:
        try:
            count, max_distance = struct.unpack("<if", read_exactly(source, 8))
        except EOFError:
            return 0
        rays = np.frombuffer(read_exactly(source, 24 * count), dtype="<f4").astype(np.float64)
        origins, directions = rays[:3 * count].reshape(count, 3), rays[3 * count:].reshape(count, 3)
        distances, normals = raycaster.cast(origins, directions, float(max_distance))
        sink.write(distances.astype("<f4").tobytes() + normals.astype("<f4").tobytes())
        sink.flush()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
