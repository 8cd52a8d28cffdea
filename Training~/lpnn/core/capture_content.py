"""Value-level checks of a capture, shared by reading, validating and writing (C#: Captures/CaptureContent.cs)."""

from __future__ import annotations

import numpy as np

from .capture import Capture
from .capture_format import SH_CHANNELS
from .schema import schema_by_id


def record_name(name: str, index: int, ids: np.ndarray) -> str:
    i, j, k = (int(v) for v in ids[index])
    return f"{name}: record {index} (id {i},{j},{k})"


def content_problems(capture: Capture, name: str, stop_at_first: bool) -> list[str]:
    """Value-level checks shared by reading, validating and writing."""
    problems: list[str] = []

    def add(message: str) -> bool:
        problems.append(message)
        return stop_at_first

    n = capture.ids.shape[0] if capture.ids.ndim == 2 else 0
    f = len(capture.feature_names)
    shapes = {
        "ids": (capture.ids, (n, 3)),
        "positions": (capture.positions, (n, 3)),
        "sh": (capture.sh, (n, 27)),
        "features": (capture.features, (n, f)),
    }
    if n < 1:
        add(f"{name}: capture has no points")
        return problems
    for key, (array, shape) in shapes.items():
        if array.shape != shape:
            add(f"{name}: section '{key}' has shape {list(array.shape)}, expected {list(shape)}")
            return problems
    if capture.labels is not None and capture.labels.shape != (n,):
        add(f"{name}: section 'labels' has shape {list(capture.labels.shape)}, expected [{n}]")
        return problems
    if not (np.isfinite(capture.cell_size) and capture.cell_size > 0):
        add(f"{name}: header: field 'cell_size': {capture.cell_size!r} is not a finite number > 0")
        return problems
    if not (np.isfinite(capture.lighting_scale) and capture.lighting_scale > 0):
        if add(f"{name}: header: field 'lighting_scale': {capture.lighting_scale!r} is not a finite number > 0"):
            return problems
    if len(set(capture.feature_names)) != f or f == 0:
        if add(f"{name}: header: field 'feature_names': must be unique and non-empty"):
            return problems
    known = schema_by_id(capture.schema)
    if known is not None and tuple(capture.feature_names) != known.names:
        if add(f"{name}: header: field 'feature_names': do not match schema {known.id!r}"):
            return problems
    if capture.labels is not None and capture.label_source is None:
        if add(f"{name}: header: field 'label_source': must be set when labels are present"):
            return problems

    ids = np.asarray(capture.ids, dtype=np.int64)
    if n > 1:
        diffs = ids[1:] - ids[:-1]
        # strictly increasing in (k, j, i) order
        later = (diffs[:, 2] > 0) | ((diffs[:, 2] == 0) & ((diffs[:, 1] > 0) | ((diffs[:, 1] == 0) & (diffs[:, 0] > 0))))
        bad = np.flatnonzero(~later)
        for index in bad[: 1 if stop_at_first else 20]:
            what = "repeats" if not diffs[index].any() else "is out of grid order after"
            if add(f"{record_name(name, int(index) + 1, ids)}: field 'ids': {what} record {int(index)}"):
                return problems

    def check_finite(key: str, array: np.ndarray, column_name) -> bool:
        bad_rows, bad_cols = np.nonzero(~np.isfinite(array))
        for row, col in list(zip(bad_rows, bad_cols))[: 1 if stop_at_first else 20]:
            value = float(array[row, col])  # plain float: numpy 2 would print 'np.float32(nan)'
            text = "NaN" if np.isnan(value) else repr(value)
            if add(f"{record_name(name, int(row), ids)}: field '{column_name(int(col))}': {text} is not finite"):
                return True
        return False

    if check_finite("positions", capture.positions, lambda c: f"positions[{'xyz'[c]}]"):
        return problems
    if check_finite("sh", capture.sh, lambda c: f"sh[{SH_CHANNELS[c // 9]},{c % 9}]"):
        return problems
    if check_finite("features", capture.features, lambda c: f"features[{capture.feature_names[c]}]"):
        return problems

    h = float(capture.cell_size)
    expected = ids.astype(np.float64) * h
    positions = capture.positions.astype(np.float64)
    tolerance = 1e-4 * h + 4.0 * np.spacing(np.abs(expected).astype(np.float32)).astype(np.float64)
    off_rows = np.flatnonzero(np.any(np.abs(positions - expected) > tolerance, axis=1))
    for row in off_rows[: 1 if stop_at_first else 20]:
        if add(f"{record_name(name, int(row), ids)}: field 'positions': {positions[row].tolist()} is not cell_size*id = {expected[row].tolist()}"):
            return problems

    if capture.labels is not None:
        bad_labels = np.flatnonzero(capture.labels > 1)
        for row in bad_labels[: 1 if stop_at_first else 20]:
            if add(f"{record_name(name, int(row), ids)}: field 'labels': {int(capture.labels[row])} is not 0 or 1"):
                return problems
    return problems
