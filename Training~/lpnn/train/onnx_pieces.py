"""Scoring a large cloud in pieces with the same scores as one piece (model-contract.md "Scoring in pieces").

The model sees one cloud per batch entry and pools it globally, so a cloud cannot simply be cut into
sub-clouds. A PointNet-style graph can still be run in three parts:

    trunk:   features (1, n, F) -> T (1, n, C)           per point: run on chunks of points
    pooling: T (1, N, C) -> the pooled tensors             the graph's own reductions, on all of T at once
    head:    T chunk + pooled tensors -> importance chunk  per point again

T is held whole (N x C float32: 276 MB for 10^6 points and C = 64) instead of every activation of the
graph (one piece: +2.7 GB at 10^6 points). The pooling part runs the graph's own nodes on the whole
T, so the pooled values are the very ones of the one-piece run, not a recombination of per-chunk
maxima and sums. The split is used only when the graph has that shape: every reduction over the
points axis (axis 1) reads one tensor T, the trunk before T holds only point-wise ops (POINTWISE_OPS:
the 1x1 layers and the reshapes around their MatMuls) and the head reduces over no points. Otherwise
`split_graph` returns None and the caller scores in one piece. Tests compare both paths
(tests/train/test_train_pieces.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import onnx
from onnx.utils import Extractor

from .modelcard import INPUT_NAME, OUTPUT_NAME

REDUCTIONS = frozenset({"ReduceMax", "ReduceMean", "ReduceMin", "ReduceSum", "ReduceProd", "ReduceL1", "ReduceL2",
                        "ReduceLogSum", "ReduceLogSumExp", "ReduceSumSquare"})
# Ops that map each point's row to that point's row (with the Shape/Gather/Concat/Cast/Reshape pattern of
# Keras' Tensordot, which flattens (1, n, C) to (n, C) around a MatMul and back).
POINTWISE_OPS = frozenset({"Sub", "Mul", "Add", "Div", "MatMul", "Conv", "Relu", "Sigmoid", "BatchNormalization",
                           "Shape", "Cast", "Gather", "Concat", "Reshape", "Identity", "Constant"})
POINTS_AXIS = 1
DEFAULT_CHUNK_POINTS = 65_536


@dataclass(frozen=True)
class GraphPieces:
    """The three serialized sub-graphs and the tensor names that join them."""

    trunk: bytes  # features -> pooled_input
    pooling: bytes  # pooled_input -> pooled
    head: bytes  # pooled_input, *pooled -> importance
    pooled_input: str
    pooled: tuple[str, ...]


def _reduces_points(node: onnx.NodeProto) -> bool:
    """A reduction whose axes include the points axis (no axes attribute: every axis)."""
    if node.op_type not in REDUCTIONS:
        return False
    for attribute in node.attribute:
        if attribute.name == "axes":
            return POINTS_AXIS in list(attribute.ints) or -2 in list(attribute.ints)
    return True  # opset <= 17 without `axes` reduces every axis; an axes *input* (opset 18) is not analysed


def split_graph(model: onnx.ModelProto) -> GraphPieces | None:
    """The trunk / pooling / head pieces of `model`, or None when its graph is not of that shape."""
    pooling_nodes = [node for node in model.graph.node if _reduces_points(node)]
    inputs = {node.input[0] for node in pooling_nodes}
    if len(inputs) != 1 or any(len(node.input) > 1 for node in pooling_nodes):
        return None
    pooled_input = inputs.pop()
    pooled = tuple(node.output[0] for node in pooling_nodes)
    typed = onnx.ModelProto()
    typed.CopyFrom(model)
    for name in (pooled_input, *pooled):  # the extractor needs a type for every cut tensor
        typed.graph.value_info.append(onnx.helper.make_tensor_value_info(name, onnx.TensorProto.FLOAT, None))
    try:
        extractor = Extractor(typed)
        trunk = extractor.extract_model([INPUT_NAME], [pooled_input])
        pooling = extractor.extract_model([pooled_input], list(pooled))
        head = extractor.extract_model([pooled_input, *pooled], [OUTPUT_NAME])
    except Exception:  # onnx raises plain exceptions for tensors it cannot type: keep the one-piece path
        return None
    if any(node.op_type not in POINTWISE_OPS for node in trunk.graph.node):
        return None
    if any(_reduces_points(node) for node in head.graph.node):
        return None
    if [i.name for i in head.graph.input] != [pooled_input, *pooled]:
        return None
    return GraphPieces(trunk=trunk.SerializeToString(), pooling=pooling.SerializeToString(),
                       head=head.SerializeToString(), pooled_input=pooled_input, pooled=pooled)


Run = Callable[[dict[str, np.ndarray]], list[np.ndarray]]


def score_in_pieces(trunk: Run, pooling: Run, head: Run, pieces: GraphPieces, features: np.ndarray,
                    chunk_points: int = DEFAULT_CHUNK_POINTS) -> np.ndarray:
    """(N, F) float32 features of one cloud -> (N,) importance, running the pieces on chunks of points.
    `trunk`, `pooling` and `head` run their piece (inputs by name -> outputs in graph order)."""
    n = features.shape[0]
    chunk = max(1, int(chunk_points))
    local: np.ndarray | None = None
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        part = trunk({INPUT_NAME: features[None, start:stop]})[0]
        if local is None:
            local = np.empty((1, n) + part.shape[2:], dtype=part.dtype)
        local[:, start:stop] = part
    assert local is not None  # n > 0: the caller scores empty clouds without a graph
    pooled = pooling({pieces.pooled_input: local})
    out = np.empty(n, dtype=np.float32)
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        feeds = {pieces.pooled_input: local[:, start:stop], **dict(zip(pieces.pooled, pooled))}
        out[start:stop] = head(feeds)[0][0]
    return out
