"""Reproducible training: the same data, config and seed give the same weights and metrics."""

from __future__ import annotations


def configure_determinism(seed: int, threads: int) -> list[str]:
    """Seeds Python, NumPy and TensorFlow, makes TF ops deterministic and fixes its thread pools.

    Returns notes about settings that could not be applied (TensorFlow fixes its thread pools at its
    first operation, so a process that already ran TF keeps its pools; results stay reproducible
    within that process, and across processes started with the same `threads`).
    """
    import keras
    import tensorflow as tf

    notes: list[str] = []
    try:
        tf.config.threading.set_intra_op_parallelism_threads(threads)
        # One inter-op thread: independent ops run one after another, in a fixed order.
        tf.config.threading.set_inter_op_parallelism_threads(1)
    except RuntimeError:
        current = tf.config.threading.get_intra_op_parallelism_threads()
        if current not in (0, threads):
            notes.append(f"TensorFlow already runs with {current} intra-op threads (asked for {threads})")
    tf.config.experimental.enable_op_determinism()
    keras.utils.set_random_seed(seed)  # Python `random`, NumPy's global RNG and TensorFlow
    return notes
