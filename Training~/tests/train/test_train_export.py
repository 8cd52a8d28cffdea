"""Export: the graph obeys the model contract (ops, opset, I/O, dynamic dims), parity with Keras
is enforced, and the model card has exactly the contract's fields."""

from __future__ import annotations

import json
import re

import numpy as np
import onnx
import pytest

from lpnn.train.checkpoint import load_checkpoint
from lpnn.train.export import ALLOWED_OPS, ExportError, check_io, check_ops, convert, parity, parity_inputs

from train_support import REPO_ROOT, TrainedModel

CONTRACT = (REPO_ROOT / "Documentation~" / "model-contract.md").read_text(encoding="utf-8")


def contract_card_example() -> dict:
    block = re.search(r"```json\n(.*?)```", CONTRACT, re.S).group(1)
    return json.loads(block)


def test_allowed_ops_equal_the_contract() -> None:
    listed = re.search(r"Allowed ops[^:]*:(.*?)\. `lpnn export`", CONTRACT, re.S).group(1)
    names = {name.strip() for name in listed.replace("\n", " ").split(",")}
    assert names == set(ALLOWED_OPS)


def test_exported_graph_obeys_the_contract(trained: TrainedModel) -> None:
    proto = onnx.load(str(trained.model))
    onnx.checker.check_model(proto)
    ops = check_ops(proto)
    assert set(ops) <= ALLOWED_OPS and {"Sub", "Mul", "ReduceMax", "ReduceMean", "Tile", "Sigmoid"} <= set(ops)
    check_io(proto, 19)
    assert [(o.domain, o.version) for o in proto.opset_import] == [("", 15)]
    dims = [d.dim_param for d in proto.graph.input[0].type.tensor_type.shape.dim[:2]]
    assert dims == ["batch", "points"]


def test_op_check_names_the_offending_ops(trained: TrainedModel) -> None:
    proto = onnx.load(str(trained.model))
    proto.graph.node.append(onnx.helper.make_node("Softmax", ["importance"], ["soft"], name="my_softmax"))
    proto.graph.node.append(onnx.helper.make_node("Gemm", ["a", "b"], ["c"], name="my_gemm"))
    with pytest.raises(ExportError, match=r"Gemm \(node 'my_gemm'\), Softmax \(node 'my_softmax'\)"):
        check_ops(proto)


def test_parity_passes_on_random_and_real_inputs_and_fails_when_the_graphs_differ(trained: TrainedModel) -> None:
    model, meta = load_checkpoint(trained.checkpoint)
    card = json.loads(trained.card.read_text(encoding="utf-8"))
    assert card["parity"]["max_abs_diff"] <= 1e-4
    assert card["parity"]["random_max_abs_diff"] is not None and card["parity"]["real_max_abs_diff"] is not None
    proto = convert(model)
    mean = np.asarray(meta["normalisation"]["mean"], np.float32)
    std = np.asarray(meta["normalisation"]["std"], np.float32)
    cases = parity_inputs(mean, std, [], seed=0)
    assert parity(model, proto, cases)["max_abs_diff"] <= 1e-4
    bias = model.output_linear.bias
    bias.assign(bias.numpy() + 0.5)  # the Keras model drifts away from the exported graph
    with pytest.raises(ExportError, match="disagree"):
        parity(model, proto, cases)


def test_model_card_has_the_contract_fields(trained: TrainedModel) -> None:
    card = json.loads(trained.card.read_text(encoding="utf-8"))
    example = contract_card_example()
    assert list(card) == list(example)  # same keys, same order
    for section in ("training", "versions", "parity", "normalisation"):
        assert set(example[section]) <= set(card[section]), section
    assert set(example["metrics"]["validation"]) <= set(card["metrics"]["validation"])
    assert card["input"] == {"name": "features", "dtype": "float32", "shape": ["batch", "points", 19]}
    assert card["output"] == {"name": "importance", "dtype": "float32", "shape": ["batch", "points"]}
    assert card["model_file"] == trained.model.name and card["opset"] == 15
    assert card["ops"] == sorted({n.op_type for n in onnx.load(str(trained.model)).graph.node})
    assert card["feature_count"] == len(card["feature_names"]) == len(card["normalisation"]["mean"]) == 19
    assert card["normalisation"]["std"][8] == 1.0  # the constant synthetic feature
    assert card["training"]["constant_features"] == ["boundary"]
    assert card["training"]["label_source"] == "synthetic:f3+0.5*f7>1.4"
    assert card["architecture"]["multiply_adds_per_point"] > 0


def test_only_the_model_files_are_left_behind(trained: TrainedModel) -> None:
    names = sorted(p.name for p in trained.model.parent.iterdir())
    assert names == ["model.card.json", "model.ckpt.npz", "model.onnx"]  # no temporary files
