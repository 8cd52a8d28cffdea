"""ONNX export: tf2onnx (opset 15, dynamic batch and points), I/O naming, op check, parity, card.

The op check enforces the model contract (ops Sentis runs on both GPUCompute and CPU); the parity
check compares onnxruntime with Keras on random and real inputs. Nothing is written unless both pass.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import onnx

from ..errors import LpnnError, UserError
from ..core.atomic import write_bytes_atomic
from .modelcard import CARD_FORMAT, CARD_VERSION, INPUT_NAME, OPSET, OUTPUT_NAME, ModelCard, card_path
from .onnx_scoring import create_session, library_versions

# Documentation~/model-contract.md "Allowed ops" (a test keeps this list and the document equal).
ALLOWED_OPS = frozenset({
    "Conv", "MatMul", "Relu", "Sigmoid", "BatchNormalization", "ReduceMax", "ReduceMean", "Add", "Sub", "Mul",
    "Div", "Concat", "Gather", "Reshape", "Slice", "Squeeze", "Unsqueeze", "Tile", "Transpose", "Cast", "Shape",
    "Expand", "Identity", "Constant",
})
DEFAULT_DOMAINS = ("", "ai.onnx")
PARITY_TOLERANCE = 1e-4
PARITY_MAX_REAL_POINTS = 50_000  # per real capture: enough to cover its value range, quick to run
DYNAMIC_DIMS = ("batch", "points")


class ExportError(LpnnError):
    """The exported graph breaks the model contract (ops, opset, I/O) or disagrees with Keras."""


def convert(model: Any) -> onnx.ModelProto:
    """Keras PointNet -> ONNX with input `features` [batch, points, F] and output `importance` [batch, points]."""
    import tensorflow as tf
    import tf2onnx

    logging.getLogger("tf2onnx").setLevel(logging.ERROR)
    spec = (tf.TensorSpec((None, None, model.feature_count), tf.float32, name=INPUT_NAME),)
    function = tf.function(lambda features: model(features, training=False), input_signature=spec)
    proto, _ = tf2onnx.convert.from_function(function, input_signature=spec, opset=OPSET)
    return _tidy(proto)


def _tidy(proto: onnx.ModelProto) -> onnx.ModelProto:
    """Contract names for the graph's input and output, named dynamic dims, no unused opset imports."""
    graph = proto.graph
    if len(graph.input) != 1 or len(graph.output) != 1:
        raise ExportError(f"expected one input and one output, got {[i.name for i in graph.input]} -> "
                          f"{[o.name for o in graph.output]}")
    renames = {graph.input[0].name: INPUT_NAME, graph.output[0].name: OUTPUT_NAME}
    for node in graph.node:
        node.input[:] = [renames.get(name, name) for name in node.input]
        node.output[:] = [renames.get(name, name) for name in node.output]
    graph.input[0].name = INPUT_NAME
    graph.output[0].name = OUTPUT_NAME
    for value in (graph.input[0], graph.output[0]):
        for dim, label in zip(value.type.tensor_type.shape.dim, DYNAMIC_DIMS):
            dim.dim_param = label  # clears any fixed value: both leading dims stay dynamic
    used_domains = {node.domain for node in graph.node} | {""}
    kept = [entry for entry in proto.opset_import if entry.domain in used_domains]
    del proto.opset_import[:]
    proto.opset_import.extend(kept)
    return proto


def used_ops(proto: onnx.ModelProto) -> list[str]:
    return sorted({node.op_type for node in proto.graph.node})


def check_ops(proto: onnx.ModelProto) -> list[str]:
    """The graph's op types; ExportError naming every op (and a node using it) outside the contract."""
    offending: dict[str, str] = {}
    for node in proto.graph.node:
        if node.domain not in DEFAULT_DOMAINS:
            offending.setdefault(f"{node.domain}:{node.op_type}", node.name)
        elif node.op_type not in ALLOWED_OPS:
            offending.setdefault(node.op_type, node.name)
    if offending:
        listed = ", ".join(f"{op} (node '{name}')" for op, name in sorted(offending.items()))
        raise ExportError(
            f"the ONNX graph uses op(s) outside the model contract: {listed}; Sentis runs only "
            f"{sorted(ALLOWED_OPS)} on both GPUCompute and CPU; change the architecture"
        )
    opsets = {entry.domain: entry.version for entry in proto.opset_import}
    default_version = opsets.get("", opsets.get("ai.onnx"))
    if default_version != OPSET:
        raise ExportError(f"the ONNX graph targets opset {default_version}, the contract requires {OPSET}")
    return used_ops(proto)


def check_io(proto: onnx.ModelProto, feature_count: int) -> None:
    """Input `features` float32 [dyn, dyn, F], output `importance` float32 [dyn, dyn]."""
    def describe(value: Any) -> tuple[str, int, list[Any]]:
        tensor = value.type.tensor_type
        return value.name, tensor.elem_type, [d.dim_param or d.dim_value for d in tensor.shape.dim]

    inputs = [describe(v) for v in proto.graph.input]
    outputs = [describe(v) for v in proto.graph.output]
    float32 = onnx.TensorProto.FLOAT
    expected_inputs = [(INPUT_NAME, float32, [*DYNAMIC_DIMS, feature_count])]
    expected_outputs = [(OUTPUT_NAME, float32, list(DYNAMIC_DIMS))]
    if inputs != expected_inputs or outputs != expected_outputs:
        raise ExportError(f"graph I/O {inputs} -> {outputs} is not {expected_inputs} -> {expected_outputs}")


NamedFeatures = tuple[str, np.ndarray]  # (capture name, (N, F) raw features)


def parity_inputs(mean: np.ndarray, std: np.ndarray, real: Sequence[NamedFeatures], seed: int) -> list[NamedFeatures]:
    """Random clouds in the training range (x3 std) of several shapes, plus real captures (one cloud each)."""
    rng = np.random.default_rng([seed, 0xFA517])
    cases = []
    for batch, points in ((1, 1), (2, 257), (1, 4096)):
        values = mean + 3.0 * std * rng.standard_normal((batch, points, mean.shape[0]))
        cases.append((f"random[{batch}x{points}]", values.astype(np.float32)))
    for name, features in real:
        if features.shape[0] > PARITY_MAX_REAL_POINTS:
            keep = np.sort(rng.choice(features.shape[0], PARITY_MAX_REAL_POINTS, replace=False))
            features = features[keep]
        cases.append((name, features[None].astype(np.float32)))
    return cases


def parity(model: Any, proto: onnx.ModelProto, cases: Sequence[NamedFeatures],
           tolerance: float = PARITY_TOLERANCE) -> dict[str, Any]:
    """Max |onnxruntime - Keras| per case; ExportError above `tolerance`."""
    session = create_session(proto.SerializeToString())
    differences: dict[str, float] = {}
    for name, features in cases:
        expected = np.asarray(model(features, training=False))
        actual = session.run([OUTPUT_NAME], {INPUT_NAME: features})[0]
        if actual.shape != expected.shape:
            raise ExportError(f"parity on {name}: onnxruntime output shape {actual.shape} != Keras {expected.shape}")
        differences[name] = float(np.max(np.abs(actual.astype(np.float64) - expected.astype(np.float64))))
    worst = max(differences.values())
    if not worst <= tolerance:  # also catches NaN
        bad = {k: v for k, v in differences.items() if not v <= tolerance}
        raise ExportError(f"onnxruntime and Keras disagree by up to {worst:.3g} (> {tolerance:g}) on {bad}")
    random_cases = [v for k, v in differences.items() if k.startswith("random[")]
    real_cases = [v for k, v in differences.items() if not k.startswith("random[")]
    return {
        "max_abs_diff": worst,
        "random_max_abs_diff": max(random_cases) if random_cases else None,
        "real_max_abs_diff": max(real_cases) if real_cases else None,
        "tolerance": tolerance,
        "cases": differences,
    }


def onnx_path(path: str | os.PathLike) -> Path:
    """The model's path; UserError unless it ends in .onnx (the card's name is derived from it)."""
    out = Path(path)
    if out.suffix != ".onnx":
        raise UserError(f"{out}: the model file name must end in .onnx")
    return out


def export_model(model: Any, meta: dict[str, Any], out_path: str | os.PathLike,
                 real_inputs: Sequence[NamedFeatures] = ()) -> ModelCard:
    """Converts, checks (ops, I/O, parity) and writes `<out>.onnx` + `<out>.card.json` atomically."""
    out = onnx_path(out_path)
    proto = convert(model)
    onnx.checker.check_model(proto)
    ops = check_ops(proto)
    check_io(proto, model.feature_count)
    mean = np.asarray(meta["normalisation"]["mean"], np.float32)
    std = np.asarray(meta["normalisation"]["std"], np.float32)
    parity_report = parity(model, proto, parity_inputs(mean, std, real_inputs, int(meta["seed"])))
    feature_count = len(meta["feature_names"])
    card = ModelCard(
        format=CARD_FORMAT,
        version=CARD_VERSION,
        model_file=out.name,
        schema=meta["schema"],
        feature_names=list(meta["feature_names"]),
        feature_count=feature_count,
        input={"name": INPUT_NAME, "dtype": "float32", "shape": [*DYNAMIC_DIMS, feature_count]},
        output={"name": OUTPUT_NAME, "dtype": "float32", "shape": list(DYNAMIC_DIMS)},
        opset=OPSET,
        ops=ops,
        normalisation={"mean": meta["normalisation"]["mean"], "std": meta["normalisation"]["std"]},
        architecture=meta["architecture"],
        training=meta["training"],
        metrics=meta["metrics"],
        versions=library_versions(include_training=True),
        parity=parity_report,
    )
    write_bytes_atomic(out, proto.SerializeToString())
    card.write(card_path(out))
    return card
