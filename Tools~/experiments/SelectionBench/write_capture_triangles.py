"""Writes the triangles `lpnn place` casts its leak rays against (lpnn.scenes.capture_geometry.capture_triangles) for the
C# Apply benchmark's raycaster (ApplyBench.cs, Tests/Core/Support/TriangleSoupRaycaster.cs). Format, little-endian:
int32 V, int32 T, then V x 3 float64 vertices (Unity metres), then T x 3 int32 vertex indices.
Usage: python write_capture_triangles.py CAPTURE.lpnncap OUT.bin   (exit 1 when the capture's geometry cannot be loaded)
"""

from __future__ import annotations

import struct
import sys

import numpy as np

from lpnn.core.atomic import write_bytes_atomic
from lpnn.core.capture_file import read_capture
from lpnn.scenes.capture_geometry import capture_triangles


def main(capture_path: str, out_path: str) -> int:
    soup, why = capture_triangles(read_capture(capture_path))
    if soup is None:
        print(f"{capture_path}: no geometry to cast leak rays against: {why}", file=sys.stderr)
        return 1
    vertices, triangles = soup
    write_bytes_atomic(out_path, struct.pack("<ii", vertices.shape[0], triangles.shape[0])
                       + np.ascontiguousarray(vertices, dtype="<f8").tobytes()
                       + np.ascontiguousarray(triangles, dtype="<i4").tobytes())
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]) if len(sys.argv) == 3 else "usage: write_capture_triangles.py CAPTURE OUT.bin")
