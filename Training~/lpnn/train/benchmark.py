"""`lpnn model bench`: onnxruntime scoring time per cloud size and training throughput, on this machine.

Scoring: `session.run` on one cloud of N random points (2 intra-op threads), median of `repeats`
runs after two warm-up runs. Training: real (unpadded) points per second through `Trainer.train_step`
with the default batch settings on synthetic captures, after the first (tracing) steps.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .config import ModelConfig, TrainConfig

DEFAULT_SIZES = (1_000, 10_000, 100_000)
THESIS_MODEL = ModelConfig(trunk=(64, 128, 256), head=(256, 128), dropout=0.3, batchnorm_momentum=0.99)
THESIS_FEATURES = 30
WARMUP_RUNS = 2
WARMUP_STEPS = 3


@dataclass(frozen=True)
class ScoringTimes:
    label: str
    feature_count: int
    multiply_adds_per_point: int | None
    median_ms: dict[int, float]  # cloud size -> median milliseconds per session.run
    min_ms: dict[int, float]  # cloud size -> fastest run (less sensitive to other processes)


def time_session(session: Any, feature_count: int, sizes: Sequence[int], repeats: int,
                 seed: int = 0) -> tuple[dict[int, float], dict[int, float]]:
    """(median ms, min ms) per cloud size."""
    from .modelcard import INPUT_NAME, OUTPUT_NAME

    rng = np.random.default_rng(seed)
    medians, minima = {}, {}
    for size in sizes:
        features = rng.standard_normal((1, size, feature_count)).astype(np.float32)
        for _ in range(WARMUP_RUNS):
            session.run([OUTPUT_NAME], {INPUT_NAME: features})
        times = []
        for _ in range(repeats):
            started = time.perf_counter()
            session.run([OUTPUT_NAME], {INPUT_NAME: features})
            times.append(time.perf_counter() - started)
        medians[size] = float(np.median(times) * 1e3)
        minima[size] = float(np.min(times) * 1e3)
    return medians, minima


def untrained_session(config: ModelConfig, feature_count: int, threads: int) -> Any:
    """An onnxruntime session of a freshly initialised network (timing does not depend on weights)."""
    from .export import check_ops, convert
    from .model import PointNet
    from .onnx_scoring import create_session

    model = PointNet(config, np.zeros(feature_count, np.float32), np.ones(feature_count, np.float32), seed=0)
    proto = convert(model)
    check_ops(proto)
    return create_session(proto.SerializeToString(), threads)


def scoring_benchmark(model_path: str | None, sizes: Sequence[int], repeats: int, threads: int,
                      compare_thesis: bool) -> list[ScoringTimes]:
    from .model import multiply_adds_per_point
    from .onnx_scoring import OnnxScorer

    rows = []
    if model_path:
        scorer = OnnxScorer(model_path, threads)
        macs = scorer.card.architecture.get("multiply_adds_per_point")
        rows.append(ScoringTimes(str(model_path), scorer.feature_count, macs,
                                 *time_session(scorer.session, scorer.feature_count, sizes, repeats)))
    else:
        default = ModelConfig()
        features = 19
        rows.append(ScoringTimes("default architecture (untrained)", features, multiply_adds_per_point(default, features),
                                 *time_session(untrained_session(default, features, threads), features, sizes, repeats)))
    if compare_thesis:
        rows.append(ScoringTimes("thesis-size network (as MatMul)", THESIS_FEATURES,
                                 multiply_adds_per_point(THESIS_MODEL, THESIS_FEATURES),
                                 *time_session(untrained_session(THESIS_MODEL, THESIS_FEATURES, threads),
                                               THESIS_FEATURES, sizes, repeats)))
    return rows


def training_throughput(steps: int, config: TrainConfig | None = None, captures: int = 8) -> dict[str, float]:
    """Real points per second through the train step (default config, synthetic captures)."""
    from .data import cloud_from_capture, normalisation_from, positive_weight
    from .batches import BatchSampler
    from .determinism import configure_determinism
    from .synthetic import synthetic_capture
    from .trainer import Trainer

    config = (config or TrainConfig()).validated()
    configure_determinism(config.seed, config.threads)
    clouds = [cloud_from_capture(synthetic_capture(seed, shape=(24, 20, 12)), f"synthetic_{seed}") for seed in range(captures)]
    trainer = Trainer(config, normalisation_from(clouds), positive_weight(clouds))
    sampler = BatchSampler(clouds, config, config.seed)
    for _ in range(WARMUP_STEPS):
        trainer.train_step(sampler.next_batch())
    batches = [sampler.next_batch() for _ in range(steps)]
    started = time.perf_counter()
    for batch in batches:
        trainer.train_step(batch)
    seconds = time.perf_counter() - started
    points = sum(b.real_points for b in batches)
    padded = sum(b.mask.size for b in batches)
    return {
        "steps": steps,
        "seconds": seconds,
        "points_per_second": points / seconds,
        "padded_fraction": 1.0 - points / padded,
        "milliseconds_per_step": seconds / steps * 1e3,
        "points_per_step": points / steps,
    }


def format_report(rows: Sequence[ScoringTimes], training: dict[str, float] | None, threads: int,
                  repeats: int) -> str:
    sizes = sorted(rows[0].median_ms)
    lines = [f"onnxruntime scoring, one cloud, {threads} intra-op thread(s), {repeats} runs: median ms (fastest ms)"]
    lines.append(f"  {'model':<36} {'F':>3} {'MAC/point':>10}" + "".join(f" {f'{s:,} pts':>18}" for s in sizes))
    for row in rows:
        macs = f"{row.multiply_adds_per_point:,}" if row.multiply_adds_per_point else "?"
        cells = "".join(f" {f'{row.median_ms[s]:.2f} ({row.min_ms[s]:.2f})':>18}" for s in sizes)
        lines.append(f"  {row.label:<36} {row.feature_count:>3} {macs:>10}{cells}")
    for row in rows:
        per_10k = ", ".join(f"{row.median_ms[s] * 10_000 / s:.2f} (at {s:,})" for s in sizes)
        lines.append(f"  {row.label}: median ms per 10k points = {per_10k}")
    for other in rows[1:]:
        ratios = ", ".join(f"{other.median_ms[s] / rows[0].median_ms[s]:.1f}x at {s:,}" for s in sizes)
        lines.append(f"  {other.label} / {rows[0].label} (median): {ratios}")
    if training:
        lines.append(
            f"training: {training['points_per_second']:,.0f} real points/s ({training['steps']} steps, "
            f"{training['milliseconds_per_step']:.1f} ms/step, {training['points_per_step']:,.0f} real points/step, "
            f"{training['padded_fraction']:.0%} padding)"
        )
    return "\n".join(lines)
