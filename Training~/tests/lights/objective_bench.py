"""Which implementation computes the light-rig objective and its gradient fastest (Documentation~/lights.md §3).
A measurement, not a test (pytest collects only test_*.py); it lives beside the tests because TensorFlow may be
imported only in lpnn.train and the tests (Tools~/lint-python.py), and its autodiff is the tests' reference.

The same objective (model.py: point lights, ambient, fixed emitters, byte clamp, fixed visibility,
area-weighted relative squared error) on one level, the same lights and visible (point, light) pairs:
  numba       the compiled analytic pass (objective_kernel.py, shipped: ForwardModel.objective), float64,
              on one thread and on every thread numba has
  numpy       the analytic gradient over (pairs, 3) arrays (ForwardModel.objective_numpy), float64
  tensorflow  automatic differentiation (GradientTape in a tf.function, gather + unsorted_segment_sum), float64
Prints the time per objective + gradient (median of REPEATS warm runs) and each one's largest gradient
difference to TensorFlow's autodiff, relative to the largest component; then the time of one visibility
refresh (model.visibility: compiled pair selection, visibility_numpy: numpy's) with Embree on 1 thread and on
all of them.

    PYTHONPATH=Training~ nice -n 19 $PY Training~/tests/lights/objective_bench.py LEVEL

tensorflow_objective is the autodiff the tests check the analytic gradients against
(test_lights_objective.py). The CLI never imports TensorFlow.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np

from lpnn.lights.model import BYTE_MAX, LINEAR_PER_BYTE, MIN_DISTANCE, POINT_SCALE, ForwardModel, Gradient, Lights

REPEATS = 7


def tensorflow_objective(model: ForwardModel, lights: Lights, visible: np.ndarray):
    """A callable (lights) -> Gradient by TensorFlow's reverse-mode autodiff of the objective's formula
    (written independently of the analytic gradients: only the forward formula is shared), float64."""
    import tensorflow as tf

    point, light = np.nonzero(visible)
    pts, nrm = tf.constant(model.points[point]), tf.constant(model.normals[point])
    pi, li = tf.constant(point), tf.constant(light)
    albedo, target = tf.constant(model.albedo), tf.constant(model.radiance)
    weight, fixed = tf.constant(model.weights[:, None]), tf.constant(model.fixed)
    basis = tf.constant(model.surface_basis)  # (S, N, 3)
    n = model.point_count
    norm = float(model.norm)

    @tf.function(reduce_retracing=True)
    def run(pos, col, inten, amb, values):
        with tf.GradientTape() as tape:
            tape.watch([pos, col, inten, amb, values])
            d = tf.gather(pos, li) - pts
            q = tf.maximum(tf.sqrt(tf.reduce_sum(d * d, 1)), 1e-9)
            ndot = tf.reduce_sum(d * nrm, 1)
            front = ndot > 0
            g = tf.where(front, tf.where(front, ndot, 0.0) / (q * tf.maximum(q * q, MIN_DISTANCE ** 2)), 0.0)
            e = tf.gather(col * inten[:, None], li)
            surfaces = tf.reduce_sum(values[:, None, None] * basis, 0)
            light_bytes = amb + fixed + surfaces + POINT_SCALE * tf.math.unsorted_segment_sum(g[:, None] * e, pi, n)
            peak = tf.reduce_max(light_bytes, 1, keepdims=True)
            scale = tf.where(peak > BYTE_MAX, BYTE_MAX / tf.maximum(peak, BYTE_MAX), tf.ones_like(peak))
            residual = albedo * LINEAR_PER_BYTE * light_bytes * scale - target
            value = tf.reduce_sum(weight * residual * residual) / norm
        return value, tape.gradient(value, [pos, col, inten, amb, values])

    def call(now: Lights) -> Gradient:
        value, grads = run(*(tf.constant(np.asarray(a, dtype=np.float64))
                             for a in (now.positions, now.colours, now.intensities, now.ambient, now.surface_values)))
        grads = [tf.convert_to_tensor(g).numpy() for g in grads]  # gathers give IndexedSlices
        return Gradient(value=float(value), positions=grads[0], colours=grads[1], intensities=grads[2],
                        ambient=grads[3], surface_values=grads[4])

    return call


def largest_difference(a: Gradient, b: Gradient) -> float:
    """The largest |a - b| over every gradient array, relative to that array's largest |b| (0 when b is 0)."""
    worst = abs(a.value - b.value) / max(abs(b.value), 1e-300)
    for key in ("positions", "colours", "intensities", "ambient", "surface_values"):
        x, y = np.asarray(getattr(a, key)), np.asarray(getattr(b, key))
        scale = float(np.max(np.abs(y))) if y.size else 0.0
        if scale > 0:
            worst = max(worst, float(np.max(np.abs(x - y))) / scale)
    return worst


def timed(run) -> tuple[float, object]:
    run()  # warm-up: compilation, tracing
    times, out = [], None
    for _ in range(REPEATS):
        started = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - started)
    return statistics.median(times), out


def main(argv: list[str] | None = None) -> int:
    import numba

    from lpnn.lights.optimise import initial_grid, initial_intensity
    from lpnn.lights.pipeline import load_scene
    from lpnn.lights.settings import DEFAULT_GRID
    from lpnn.scenes.levels import load_level

    parser = argparse.ArgumentParser(prog="objective_bench.py", description=__doc__.split("\n")[0])
    parser.add_argument("level", help="a level, written as for lpnn scene import")
    args = parser.parse_args(argv)
    level = load_level(args.level)
    scene = load_scene(level)
    m = scene.model
    lights = initial_intensity(m, initial_grid(scene.bounds[0], scene.bounds[1], DEFAULT_GRID, scene.is_open))
    lights.positions = lights.positions + 3.0  # off the grid's symmetric start
    lights.colours = np.clip(1.0 - np.linspace(0.0, 0.4, lights.count)[:, None] * np.array([0.0, 1.0, 0.5]), 0, 1)
    lights.ambient = np.array([20.0, 15.0, 10.0])
    visible = m.visibility(lights)
    pairs = int(visible.sum())
    print(f"{level.name}: {m.point_count:,} target points, {lights.count} lights, {pairs:,} visible pairs "
          f"({pairs / max(visible.size, 1):.1%} of all)")
    autodiff = tensorflow_objective(m, lights, visible)
    rows = []
    threads = numba.config.NUMBA_NUM_THREADS
    def numba_on(count: int):
        def run():
            m.threads = count
            return m.objective(lights, visible)
        return run

    for name, run in (("numba analytic, 1 thread (shipped)", numba_on(1)),
                      (f"numba analytic, {threads} threads", numba_on(threads)),
                      ("numpy analytic", lambda: m.objective_numpy(lights, visible)),
                      ("tensorflow autodiff", lambda: autodiff(lights))):
        seconds, out = timed(run)
        rows.append((name, seconds, out))
    reference = rows[-1][2]
    for name, seconds, out in rows:
        print(f"{name:32s} {seconds * 1000:7.1f} ms per objective + gradient; objective {out.value:.12f}; "
              f"largest difference to autodiff {largest_difference(out, reference):.1e}")
    same = np.array_equal(m.visibility(lights), m.visibility_numpy(lights))
    threads = m.raycaster.threads
    for raycaster_threads in sorted({1, threads}):
        m.raycaster.threads = raycaster_threads
        for name, run in (("compiled", lambda: m.visibility(lights)), ("numpy", lambda: m.visibility_numpy(lights))):
            seconds, _ = timed(run)
            print(f"visibility refresh, {name} pair selection, Embree on {raycaster_threads} thread(s): "
                  f"{seconds * 1000:7.0f} ms")
    m.raycaster.threads = threads
    print(f"compiled and numpy visibility {'identical' if same else 'DIFFER'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
