"""Objective curves of a fit: CSV (one row per iteration) and PNG (objective vs iteration, log scale)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from ..core.atomic import write_text_atomic
from ..quality.bench.plots import pyplot, save_png
from .optimise import CurvePoint

COLUMNS = ("phase", "algorithm", "iteration", "evaluations", "objective", "penalty", "seconds", "rays")


def write_curve_csv(path: Path, curve: list[CurvePoint]) -> Path:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for point in curve:
        writer.writerow([point.phase, point.algorithm, point.iteration, point.evaluations, f"{point.objective:.9g}",
                         f"{point.penalty:.9g}", f"{point.seconds:.4f}", point.rays])
    return write_text_atomic(path, buffer.getvalue())


def write_curve_png(path: Path, curves: dict[str, list[CurvePoint]], title: str) -> Path:
    """One line per scheme (label -> curve)."""
    plt = pyplot()
    figure, axes = plt.subplots(figsize=(7, 4.5))
    for label, curve in curves.items():
        axes.plot([p.iteration for p in curve], np.maximum([p.objective for p in curve], 1e-9), label=label)
    axes.set_yscale("log")
    axes.set_xlabel("iteration (Adam step or L-BFGS iteration)")
    axes.set_ylabel("objective (relative squared error)")
    axes.set_title(title)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    return save_png(plt, figure, path)
