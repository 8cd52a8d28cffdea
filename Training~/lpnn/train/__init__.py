"""Trainer: captures -> PointNet-style importance model -> validated ONNX model + model card.

One responsibility per module: `config` (options), `data` (load, check, split captures), `batches`
(crops, subsamples, padded batches), `model` (the network), `losses`, `metrics`, `determinism`,
`trainer` (the loop), `diagnostics` (BatchNorm check), `summary` + `checkpoint` (what a trained model
records), `export` (ONNX, op check, parity), `modelcard`, `onnx_scoring` (OnnxScorer), `model_check`,
`pipeline` (the jobs behind `lpnn train`/`export`), `synthetic` (test data), `benchmark`.
TensorFlow is imported only by the modules that need it: data, metrics, the card and scoring stay light.
"""

import os as _os

# Before any TensorFlow import: keep its start-up INFO/WARNING chatter off the console.
_os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "2")
