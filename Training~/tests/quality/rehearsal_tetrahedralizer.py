"""The rehearsal's tetrahedraliser (Tests/Core/ApplyRehearsalTests.cs): Python's own, served over stdin/stdout.

A level's lattice is cospherical, so its Delaunay tetrahedralisation is not unique; lpnn.quality.metric.triangulation breaks
the ties with a deterministic height per world position, and the C# test stand-in (BowyerWatsonDelaunay) needs points
in general position and is O(n^2). So the rehearsal asks this process for every tetrahedralisation: each probe set is
mapped to the capture's points and tetrahedralised exactly as `lpnn place` does (the field's frame, the capture's own
float positions). Protocol (little-endian): request int32 K, then K x 3 float32 positions; reply int32 T, then T x 4
int32 indices into the request, or T = -1 and an int32-length UTF-8 message when the set cannot be tetrahedralised.
Run as: python rehearsal_tetrahedralizer.py CAPTURE
"""

from __future__ import annotations

import struct
import sys

import numpy as np
from scipy.spatial import cKDTree

from lpnn.core.capture_file import read_capture
from lpnn.core.pipe_protocol import read_exactly
from lpnn.quality.metric.metric import ReferenceField
from lpnn.quality.metric.triangulation import GeometryError, tetrahedralize


def main(capture_path: str) -> int:
    field = ReferenceField.from_capture(read_capture(capture_path))
    tree = cKDTree(field.world)
    source, sink = sys.stdin.buffer, sys.stdout.buffer
    while True:
        try:
            (count,) = struct.unpack("<i", read_exactly(source, 4))
        except EOFError:
            return 0
        asked = np.frombuffer(read_exactly(source, 12 * count), dtype="<f4").reshape(count, 3).astype(np.float64)
        distance, indices = tree.query(asked)
        if count and float(distance.max()) > 1e-3:
            message = f"a probe at {asked[int(distance.argmax())].tolist()} is not a point of the capture".encode()
            sink.write(struct.pack("<ii", -1, len(message)) + message)
        else:
            try:
                tets = tetrahedralize(field.world[indices], field.frame).tets.astype("<i4")
                sink.write(struct.pack("<i", tets.shape[0]) + tets.tobytes())
            except GeometryError as exc:
                message = str(exc).encode()
                sink.write(struct.pack("<ii", -1, len(message)) + message)
        sink.flush()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
