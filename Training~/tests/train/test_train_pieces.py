"""Scoring in pieces (onnx_pieces.py): bit-identical to one piece where the graph allows it, one piece
otherwise."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import onnx
from onnx import TensorProto, helper

from lpnn.train.onnx_pieces import split_graph
from lpnn.train.onnx_scoring import OnnxScorer
from lpnn.train.synthetic import synthetic_capture

from train_support import TrainedModel

SHIPPED = Path(__file__).resolve().parents[3] / "Packages" / "com.lpnn.probes" / "Models" / "lpnn_default.onnx"


def _features(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    # Wide, skewed values: a pooled max and mean that a per-chunk recombination would get wrong.
    return (rng.normal(size=(count, 19)) * rng.uniform(0.1, 5.0, size=19) + rng.normal(size=19)).astype(np.float32)


def test_the_shipped_model_scores_in_pieces_exactly_as_in_one(tmp_path: Path) -> None:
    features = _features(50_001, 0)
    whole = OnnxScorer(SHIPPED, chunk_points=None).score(features)
    pieces = OnnxScorer(SHIPPED, chunk_points=7_000)  # 8 chunks, the last one short
    scores = pieces.score(features)
    assert pieces._pieces is not None  # really split, not the one-piece fallback
    np.testing.assert_array_equal(scores, whole)
    # A cloud no larger than the chunk size takes the one-piece path.
    np.testing.assert_array_equal(pieces.score(features[:7_000]), OnnxScorer(SHIPPED, chunk_points=None).score(features[:7_000]))


def test_a_trained_model_scores_in_pieces_exactly_as_in_one(trained: TrainedModel) -> None:
    capture = synthetic_capture(3, shape=(30, 20, 10))  # 6,000 points
    whole = OnnxScorer(trained.model, chunk_points=None).score_capture(capture)
    pieces = OnnxScorer(trained.model, chunk_points=1_000)
    np.testing.assert_array_equal(pieces.score_capture(capture), whole)
    assert pieces._pieces is not None


def _graph(reduce_in_trunk: bool) -> onnx.ModelProto:
    """features -> Relu -> [x, max over points] -> ReduceMean over channels -> importance; with
    reduce_in_trunk the Relu reads a points-pooled tensor (not point-wise: never split)."""
    features = helper.make_tensor_value_info("features", TensorProto.FLOAT, ["batch", "points", 2])
    importance = helper.make_tensor_value_info("importance", TensorProto.FLOAT, ["batch", "points"])
    nodes = []
    if reduce_in_trunk:
        nodes += [helper.make_node("ReduceMean", ["features"], ["centre"], axes=[1], keepdims=1),
                  helper.make_node("Sub", ["features", "centre"], ["shifted"])]
    nodes += [helper.make_node("Relu", ["shifted" if reduce_in_trunk else "features"], ["local"]),
              helper.make_node("ReduceMax", ["local"], ["pooled"], axes=[1], keepdims=1),
              helper.make_node("Sub", ["local", "pooled"], ["relative"]),
              helper.make_node("ReduceMean", ["relative"], ["mean"], axes=[2], keepdims=0),
              helper.make_node("Sigmoid", ["mean"], ["importance"])]
    graph = helper.make_graph(nodes, "g", [features], [importance])
    return helper.make_model(graph, opset_imports=[helper.make_opsetid("", 15)])


def test_only_point_wise_trunks_are_split() -> None:
    assert split_graph(_graph(reduce_in_trunk=False)) is not None
    assert split_graph(_graph(reduce_in_trunk=True)) is None  # two tensors pooled over the points
