"""Headless scoring with onnxruntime: `OnnxScorer(model_path).score(features) -> importance`.

The session is created once per scorer (2 intra-op threads) and reused; the model card beside the
model is checked against the features' schema before anything is scored. No TensorFlow here.
Clouds of more than `chunk_points` points are scored in pieces (onnx_pieces.py: the same scores,
a fraction of the memory) when the graph allows it.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import onnxruntime as ort

from .. import __version__
from ..errors import UserError
from .modelcard import INPUT_NAME, OUTPUT_NAME, ModelCard, card_path, check_features
from .onnx_pieces import DEFAULT_CHUNK_POINTS, GraphPieces, score_in_pieces, split_graph

DEFAULT_THREADS = 2


def create_session(model: bytes | str | os.PathLike, threads: int = DEFAULT_THREADS) -> ort.InferenceSession:
    """A CPU onnxruntime session with a fixed thread count (results and timings repeatable)."""
    options = ort.SessionOptions()
    options.intra_op_num_threads = threads
    options.inter_op_num_threads = 1
    options.execution_mode = ort.ExecutionMode.ORT_SEQUENTIAL
    options.log_severity_level = 3
    source = model if isinstance(model, bytes) else str(model)
    return ort.InferenceSession(source, options, providers=["CPUExecutionProvider"])


def library_versions(include_training: bool) -> dict[str, str]:
    """Versions recorded in model cards (training libraries are imported only when asked for)."""
    import onnx

    versions = {"lpnn": __version__}
    if include_training:
        import keras
        import tensorflow as tf
        import tf2onnx

        versions.update(tensorflow=tf.__version__, keras=keras.__version__, tf2onnx=tf2onnx.__version__)
    versions.update(onnx=onnx.__version__, onnxruntime=ort.__version__)
    return versions


class OnnxScorer:
    """Scores the points of one cloud (one capture) with an exported LPNN model and its card."""

    def __init__(self, model_path: str | os.PathLike, threads: int = DEFAULT_THREADS,
                 chunk_points: int | None = DEFAULT_CHUNK_POINTS):
        """chunk_points: clouds larger than this are scored in pieces when the graph allows it
        (onnx_pieces.py); None scores every cloud in one piece."""
        self.model_path = Path(model_path)
        self.threads = threads
        self.chunk_points = chunk_points
        self._pieces: tuple[GraphPieces, list[ort.InferenceSession]] | None = None
        if not self.model_path.is_file():
            raise UserError(f"{self.model_path}: model not found")
        self.card: ModelCard = ModelCard.read(card_path(self.model_path))
        try:
            self.session = create_session(self.model_path, threads)
        except Exception as exc:  # onnxruntime raises its own exception types for unreadable graphs
            raise UserError(f"{self.model_path}: onnxruntime cannot load the model: {exc}") from exc
        inputs = [(i.name, i.shape) for i in self.session.get_inputs()]
        outputs = [o.name for o in self.session.get_outputs()]
        if len(inputs) != 1 or inputs[0][0] != INPUT_NAME or outputs != [OUTPUT_NAME]:
            raise UserError(f"{self.model_path}: graph I/O {inputs} -> {outputs} is not "
                            f"'{INPUT_NAME}' -> '{OUTPUT_NAME}' (model-contract.md)")
        if inputs[0][1][-1] != self.card.feature_count:
            raise UserError(f"{self.model_path}: the graph reads {inputs[0][1][-1]} features but its card "
                            f"{card_path(self.model_path).name} says {self.card.feature_count}")

    @property
    def feature_count(self) -> int:
        return self.card.feature_count

    def check_schema(self, schema: str, feature_names: Sequence[str], source: str = "the features") -> None:
        """UserError naming both schemas when features of `schema` cannot be fed to this model."""
        check_features(self.card.schema, self.card.feature_names, self.card.model_file, schema, feature_names, source)

    def check_capture(self, capture: Any, name: str = "the capture") -> None:
        self.check_schema(capture.schema, capture.feature_names, name)

    def score(self, features: np.ndarray) -> np.ndarray:
        """(N, F) raw features of ONE cloud -> (N,) float32 importance in [0, 1]."""
        values = np.ascontiguousarray(features, dtype=np.float32)
        if values.ndim != 2 or values.shape[1] != self.feature_count:
            raise UserError(f"features have shape {list(values.shape)}, expected [points, {self.feature_count}] "
                            f"(schema '{self.card.schema}')")
        if values.shape[0] == 0:
            return np.zeros(0, dtype=np.float32)
        if not np.all(np.isfinite(values)):
            row = int(np.flatnonzero(~np.all(np.isfinite(values), axis=1))[0])
            raise UserError(f"features of point {row} are not finite: {values[row].tolist()}")
        if self.chunk_points is not None and values.shape[0] > self.chunk_points:
            pieces = self._graph_pieces()
            if pieces is not None:
                split, (trunk, pooling, head) = pieces
                return score_in_pieces(lambda feeds: trunk.run(None, feeds), lambda feeds: pooling.run(None, feeds),
                                       lambda feeds: head.run(None, feeds), split, values, self.chunk_points)
        output = self.session.run([OUTPUT_NAME], {INPUT_NAME: values[None]})[0]
        return np.ascontiguousarray(output[0], dtype=np.float32)

    def _graph_pieces(self) -> tuple[GraphPieces, list[ort.InferenceSession]] | None:
        """The graph split for scoring in pieces and a session per piece (built on first use), or None."""
        if self._pieces is None:
            import onnx

            split = split_graph(onnx.load(str(self.model_path)))
            if split is None:
                self.chunk_points = None  # not splittable: one piece from now on
                return None
            self._pieces = (split, [create_session(part, self.threads)
                                    for part in (split.trunk, split.pooling, split.head)])
        return self._pieces

    def score_capture(self, capture: Any, name: str = "the capture") -> np.ndarray:
        self.check_capture(capture, name)
        return self.score(capture.features)
