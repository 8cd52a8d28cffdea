"""Benchmark figures: error vs probes and time vs probes, per capture (matplotlib, Agg, PNG, atomic)."""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from ...core.atomic import write_bytes_atomic
from .results import CaptureResult

METHOD_STYLE = {
    "uniform": ("tab:gray", "s"),
    "random": ("tab:brown", "x"),
    "heuristic": ("tab:orange", "^"),
    "network-topk": ("tab:cyan", "p"),
    "network": ("tab:blue", "o"),
    "guided": ("tab:red", "*"),
    "guided-refined": ("tab:pink", "P"),
    "guided-exact-refined": ("navy", "h"),
    "insertion": ("black", "+"),
    "insertion-refined": ("olive", "X"),
    "fast-reference": ("tab:green", "D"),
    "blockwise-reference": ("darkgreen", "d"),
    "faithful-reference": ("tab:purple", "v"),
}


def pyplot():
    """matplotlib.pyplot on the headless Agg backend."""
    import matplotlib

    matplotlib.use("Agg")  # headless; must precede pyplot
    import matplotlib.pyplot as plt

    return plt


def save_png(plt, figure, path: Path, dpi: int = 120) -> Path:
    """The figure as a PNG written atomically (no software tag: same input, same bytes)."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi, metadata={"Software": None})
    plt.close(figure)
    return write_bytes_atomic(path, buffer.getvalue())


def _positive(values: np.ndarray) -> np.ndarray:
    """Log axes cannot show 0: clamp to a visible floor."""
    return np.maximum(values, 1e-6)


def error_plot(result: CaptureResult, path: str | os.PathLike) -> Path:
    plt = pyplot()
    figure, axes = plt.subplots(figsize=(7, 4.5))
    curve = result.reference_curve
    counts = np.flatnonzero(np.isfinite(curve) & (np.arange(curve.shape[0]) >= 4))
    axes.plot(counts, _positive(curve[counts]), color="tab:green", linewidth=0.8, alpha=0.6,
              label="fast reference (every count)" if result.yardstick == "fast-reference"
              else f"{result.yardstick} (counts evaluated)", marker=None if result.yardstick == "fast-reference" else ".")
    for method, (colour, marker) in METHOD_STYLE.items():
        rows = sorted((r for r in result.rows if r.method == method and r.policy == "budget"), key=lambda r: r.probes)
        if rows:
            axes.plot([r.probes for r in rows], _positive(np.array([r.mean_error for r in rows])), marker=marker,
                      color=colour, label=f"{method} (budgets)")
        for r in (r for r in result.rows if r.method == method and r.policy == "tolerance"):
            axes.scatter([r.probes], _positive(np.array([r.mean_error])), marker="*", s=120, color=colour,
                         edgecolors="black", linewidths=0.5, zorder=5)
    tolerance = [r.parameter for r in result.rows if r.policy == "tolerance"]
    if tolerance:
        axes.axhline(tolerance[0], color="black", linestyle=":", linewidth=0.8, label=f"tolerance {tolerance[0]:g} (stars)")
    axes.set_xscale("log")
    axes.set_yscale("log")
    shown = [r.mean_error for r in result.rows if r.mean_error > 0]
    if shown:  # the reference curve falls to 0 at N: keep the methods' range readable
        axes.set_ylim(bottom=min(shown) / 3.0)
    axes.set_xlabel("probes kept")
    axes.set_ylabel("mean relative irradiance error")
    axes.set_title(f"{result.name}: error vs probes ({result.points:,} candidates)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7)
    figure.tight_layout()
    return save_png(plt, figure, Path(path))


def time_plot(result: CaptureResult, path: str | os.PathLike) -> Path:
    plt = pyplot()
    figure, axes = plt.subplots(figsize=(7, 4.5))
    for method, (colour, marker) in METHOD_STYLE.items():
        rows = sorted((r for r in result.rows if r.method == method and r.policy == "budget"), key=lambda r: r.probes)
        if rows:
            axes.plot([r.probes for r in rows], _positive(np.array([r.seconds for r in rows])) * 1000.0,
                      marker=marker, color=colour, label=method)
        for r in (r for r in result.rows if r.method == method and r.policy == "tolerance"):
            axes.scatter([r.probes], [max(r.seconds, 1e-6) * 1000.0], marker="*", s=120, color=colour,
                         edgecolors="black", linewidths=0.5, zorder=5)
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("probes kept")
    axes.set_ylabel("time to place (ms, log)")
    axes.set_title(f"{result.name}: time vs probes (stars: tolerance policy)")
    axes.grid(True, which="both", alpha=0.3)
    if axes.get_legend_handles_labels()[0]:  # tolerance rows alone (--no-budgets) have no labelled line
        axes.legend(fontsize=7)
    figure.tight_layout()
    return save_png(plt, figure, Path(path))
