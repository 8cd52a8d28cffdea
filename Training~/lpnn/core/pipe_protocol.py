"""Reading a fixed-size binary message from a pipe: the helper processes that serve Python's answers to the C# core's
tests and benchmarks over stdin/stdout (Training~/tests/quality/rehearsal_tetrahedralizer.py,
Tools~/experiments/SelectionBench/embree_raycaster_server.py)."""

from __future__ import annotations

from typing import BinaryIO


def read_exactly(stream: BinaryIO, size: int) -> bytes:
    """`size` bytes from `stream`, reading until they have all come; EOFError when the stream ends first."""
    data = bytearray()
    while len(data) < size:
        chunk = stream.read(size - len(data))
        if not chunk:
            raise EOFError
        data.extend(chunk)
    return bytes(data)
