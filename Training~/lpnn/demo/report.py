"""What the demo prints and writes: a table, a PNG (error vs probes; the chosen probes seen from above),
the probe files Unity imports (`file-formats.md` probe file) and a JSON summary."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..core.atomic import write_text_atomic
from ..core.in_use_section import capture_rule, in_use_label, in_use_text
from ..quality.metric.metric import guarded_ratio
from ..quality.bench.plots import pyplot, save_png
from ..quality.placement.methods import BY_NAME
from ..quality.placement.probes_file import write_probes_json
from .run import PRIMARY, DemoResult

STYLE = {"insertion-refined": ("olive", "-"), "guided-refined": ("tab:pink", "-"), "guided": ("tab:purple", "-"), "network": ("tab:blue", "-"), "guided-exact-refined": ("navy", "-"),
         "fast-reference": ("tab:green", "-"), "leak-aware-reference": ("darkgreen", "-"), "uniform": ("tab:gray", "--"),
         "heuristic": ("tab:orange", "--"),
         "insertion": ("tab:red", "--")}
STAGES = ("features", "inference", "selection", "refinement", "reference")


def table(result: DemoResult) -> str:
    n = result.capture.point_count
    held = {True: "held out: never seen in training or model selection",
            False: "NOT held out: the model was trained on this level",
            None: "the model card does not list its held-out levels"}[result.held_out]
    reference = result.methods["fast-reference"]
    uniform = result.methods["uniform"]
    seconds = result.import_seconds
    lines = [f"{result.level}: {n:,} evaluation points at {result.capture.cell_size:g} m ({held})",
             in_use_line(result),
             "import: " + ", ".join(f"{k} {v:.2f} s" for k, v in seconds.items()),
             f"import and placement kernels compiled before timing: {result.compile_seconds:.2f} s (numba; near 0 once cached)",
             "",
             f"Tolerance policy: fewest probes with mean irradiance error <= {result.tolerance:g}",
             f"{'method':<22}{'label':<36}{'probes':>8}{'% pts':>7}{'x ref':>7}{'x unif':>7}{'mean err':>10}{'p95 err':>9}"
             f"{'in use':>8}{'leaks':>8}  time per stage"]
    for name in ("insertion-refined", "guided-refined", "guided", "network", "guided-exact-refined", "fast-reference",
                 "leak-aware-reference", "insertion", "heuristic", "uniform"):
        if name not in result.methods:  # the leak-aware reference: only where the level's geometry is known
            continue
        m = result.methods[name]
        stages = ", ".join(f"{stage} {m.seconds[stage] * 1e3:.0f} ms" for stage in STAGES if stage in m.seconds)
        lines.append(f"{name:<22}{BY_NAME[name].label:<36}{m.probes:>8}{100 * m.probes / n:>6.1f}%"
                     f"{guarded_ratio(m.probes, reference.probes):>7.2f}{guarded_ratio(m.probes, uniform.probes):>7.2f}"
                     f"{m.quality.irradiance.mean:>10.4f}{m.quality.irradiance.p95:>9.4f}"
                     f"{in_use_text(m.quality.in_use_error):>8}{percent_text(m.quality.leaking):>8}  {stages}")
    count = result.methods[PRIMARY].probes
    same = result.same_count
    primary_error = same[PRIMARY].irradiance.mean
    others = ", ".join(f"{name} {same[name].irradiance.mean:.4f} "
                       f"(default x{guarded_ratio(primary_error, same[name].irradiance.mean):.2f})"
                       for name in ("fast-reference", "guided", "insertion", "network", "uniform", "heuristic"))
    lines += ["", f"At the default's {count} probes ({PRIMARY}): mean error {primary_error:.4f}; "
              f"the rankings' first {count} probes: {others}"]
    aware = result.methods.get("leak-aware-reference")
    if aware is not None:  # x ref above is against the leak-blind reference; the default is leak-aware
        lines += ["", f"Against the leak-aware reference (the exact greedy of the leak-weighted error the default "
                  f"refines, {aware.probes} probes at tau): the default keeps "
                  f"x{guarded_ratio(count, aware.probes):.3f} its probes, the leak-blind reference "
                  f"x{guarded_ratio(reference.probes, aware.probes):.3f}"]
    whole = result.every_point_default
    if whole is not None:
        total = sum(whole.seconds.values())
        lines += ["", f"The default on every point instead (rule all, {result.every_point.point_count:,} points, the "
                  f"old behaviour): {whole.probes} probes, mean error {whole.quality.irradiance.mean:.4f} over all "
                  f"points but {in_use_text(whole.quality.in_use_error)} at the points in use, where "
                  f"{percent_text(whole.quality.leaking)} leak; placement {total:.2f} s "
                  f"(in use: {sum(result.methods[PRIMARY].seconds.values()):.2f} s)"]
    # The demo's level has no artist's probes: every method above places from scratch (Documentation~/pins.md;
    # `lpnn place --keep PINS.json` keeps given ones).
    lines += ["", "Pinned probes: 0 (no artist's probes on this level; lpnn place --keep PINS.json keeps given ones, "
              "Documentation~/pins.md)"]
    return "\n".join(lines) + "\n"


def percent_text(share: float) -> str:
    """A share as a percentage with one decimal; "n/a" when not known."""
    return "n/a" if share != share else f"{100 * share:.1f}%"


def _number(value: float) -> float | None:
    """JSON has no NaN: an error the capture cannot give is null."""
    return None if value != value else value


def in_use_line(result: DemoResult) -> str:
    """Which points the demo places on (in-use.md)."""
    source = result.capture.source
    rule = capture_rule(result.capture)
    if rule == "all":  # every point placed; the section, when there is one, says which are in use
        return f"points in use: {in_use_label(result.capture)} (every point of the volume placed)"
    return (f"points in use: {rule} ({result.capture.point_count:,} of {source.get('points_before_in_use', 0):,} "
            f"points within {source.get('in_use_band_height', 0):g} m above walkable floors"
            + (f", reached from the level's {source.get('in_use_seeds', 0)} spawns and items)" if rule == "reachable" else ")"))


def plot(result: DemoResult, path: Path) -> Path:
    plt = pyplot()
    figure, (curves, view) = plt.subplots(1, 2, figsize=(12, 4.8))
    for name, (counts, errors) in result.curves.items():
        colour, style = STYLE[name]
        shown = np.isfinite(errors) & (errors > 0)
        curves.plot(counts[shown], errors[shown], style, color=colour, linewidth=1.2, label=f"{BY_NAME[name].label} ({name})")
    for name, method in result.methods.items():
        colour, _ = STYLE[name]
        curves.scatter([method.probes], [max(method.quality.irradiance.mean, 1e-6)], marker="*", s=140,
                       color=colour, edgecolors="black", linewidths=0.5, zorder=5)
    curves.axhline(result.tolerance, color="black", linestyle=":", linewidth=0.8,
                   label=f"tolerance {result.tolerance:g} (stars: each method's answer)")
    curves.set_xscale("log")
    curves.set_yscale("log")
    answers = [m.quality.irradiance.mean for m in result.methods.values() if m.quality.irradiance.mean > 0]
    curves.set_ylim(bottom=min(answers + [result.tolerance]) / 4.0)  # every curve falls to 0 at N
    curves.set_xlabel("probes kept")
    curves.set_ylabel("mean relative irradiance error")
    curves.set_title(f"{result.level}: error vs probes ({result.capture.point_count:,} candidates)")
    curves.grid(True, which="both", alpha=0.3)
    curves.legend(fontsize=7)

    positions = result.capture.positions.astype(np.float64)
    chosen = positions[result.methods[PRIMARY].indices]
    order = np.argsort(positions[:, 1])  # draw low points first, seen from above (Unity: y up)
    points = view.scatter(positions[order, 0], positions[order, 2], c=result.scores[order], s=6, cmap="viridis",
                          vmin=0.0, vmax=1.0, alpha=0.6, linewidths=0)
    view.scatter(chosen[:, 0], chosen[:, 2], s=28, facecolors="none", edgecolors="red", linewidths=0.9,
                 label=f"probes of the default ({chosen.shape[0]})")
    figure.colorbar(points, ax=view, label="LPNN score")
    view.set_aspect("equal")
    view.set_xlabel("x (m)")
    view.set_ylabel("z (m)")
    view.set_title("scores and the default's probes (top view)")
    view.legend(fontsize=7, loc="upper right")
    figure.tight_layout()
    return save_png(plt, figure, path, dpi=110)


def write_outputs(result: DemoResult, out: Path, model_name: str) -> dict[str, Path]:
    """probes.json (insertion-refined, the main result: the package's default), probes-batched.json (guided-refined),
    probes-guided.json (guided), probes-spread.json (network: the milliseconds tier), probes-refined.json
    (guided-exact-refined), demo.png, summary.json, table.txt."""
    out.mkdir(parents=True, exist_ok=True)
    capture = result.capture
    files: dict[str, Path] = {}
    for name, file in ((PRIMARY, "probes.json"), ("guided-refined", "probes-batched.json"), ("guided", "probes-guided.json"),
                       ("network", "probes-spread.json"), ("guided-exact-refined", "probes-refined.json")):
        method = result.methods[name]
        files[name] = write_probes_json(
            out / file, capture.positions[method.indices], capture.units,
            {"level": result.level, "method": name, "model": model_name, "policy": "tolerance",
             "tolerance": result.tolerance, "mean_error": round(method.quality.irradiance.mean, 6),
             "p95_error": round(method.quality.irradiance.p95, 6)})
    files["plot"] = plot(result, out / "demo.png")
    text = table(result)
    files["table"] = write_text_atomic(out / "table.txt", text)
    summary = {"level": result.level, "points": capture.point_count, "cell_size": capture.cell_size,
               "held_out": result.held_out, "tolerance": result.tolerance, "model": model_name,
               "import_seconds": result.import_seconds, "compile_seconds": result.compile_seconds, "in_use": capture_rule(capture),
               "points_before_in_use": capture.source.get("points_before_in_use", capture.point_count),
               "methods": {name: {"probes": m.probes, "mean_error": m.quality.irradiance.mean,
                                  "in_use_error": _number(m.quality.in_use_error),
                                  "leaking": _number(m.quality.leaking),
                                  "p95_error": m.quality.irradiance.p95, "smape_mean": m.quality.smape.mean,
                                  "seconds": m.seconds} for name, m in result.methods.items()},
               "primary": PRIMARY,
               "at_primary_count": {name: q.irradiance.mean for name, q in result.same_count.items()}}
    whole = result.every_point_default
    if whole is not None:
        summary["every_point_default"] = {"points": result.every_point.point_count, "probes": whole.probes,
                                          "mean_error": whole.quality.irradiance.mean,
                                          "in_use_error": _number(whole.quality.in_use_error),
                                          "leaking": _number(whole.quality.leaking), "seconds": whole.seconds}
    files["summary"] = write_text_atomic(out / "summary.json", json.dumps(summary, indent=2, allow_nan=False) + "\n")
    return files
