"""Which library computes the light-rig objective and its gradient best (Documentation~/lights.md §3).

The same objective (model.py: point lights, ambient, byte clamp, fixed visibility, area-weighted
relative squared error) on one level, with the same lights and the same visible (point, light) pairs:
  numpy       the shipped analytic gradient (lpnn.lights.model), float64
  tensorflow  automatic differentiation (GradientTape, tf.function, gather + unsorted_segment_sum), float64
  drjit       Mitsuba 3 / Dr.Jit `llvm_ad_rgb` automatic differentiation (gather + scatter_reduce), float32
and the shadow rays of one visibility refresh with Embree (embreex, shipped) and Mitsuba's ray_test.
Prints time per objective + gradient (median of REPEATS warm runs), the largest gradient difference
to numpy, and rays/s. Libraries that are not installed are reported as such.

    PYTHONPATH=Training~ $PY Tools~/experiments/lights-backends.py LEVEL
(Mitsuba is not a project dependency: to include it, run with a Python that has `mitsuba` installed
and the project's packages on its path; Dr.Jit needs libLLVM >= 15 that can compile for this CPU,
see Documentation~/lights.md §3.)
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np

from lpnn.lights.model import BYTE_MAX, LINEAR_PER_BYTE, MIN_DISTANCE, POINT_SCALE, RAY_OFFSET
from lpnn.lights.optimise import initial_grid, initial_intensity
from lpnn.lights.pipeline import load_scene
from lpnn.lights.settings import DEFAULT_GRID
from lpnn.scenes.levels import load_level
from lpnn.scenes.surfaces import ray_geometry

REPEATS = 5


def timed(run) -> tuple[float, object]:
    run()  # warm-up: tracing, JIT compilation
    times, out = [], None
    for _ in range(REPEATS):
        started = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - started)
    return statistics.median(times), out


def tensorflow_objective(m, lights, point, light):
    import tensorflow as tf

    pts, nrm = tf.constant(m.points[point]), tf.constant(m.normals[point])
    pi, li = tf.constant(point), tf.constant(light)
    albedo, target, weight = tf.constant(m.albedo), tf.constant(m.radiance), tf.constant(m.weights[:, None])
    pos, col, inten = tf.Variable(lights.positions), tf.Variable(lights.colours), tf.Variable(lights.intensities)
    amb = tf.Variable(lights.ambient)
    n = m.point_count

    @tf.function
    def run():
        with tf.GradientTape() as tape:
            d = tf.gather(pos, li) - pts
            q = tf.sqrt(tf.reduce_sum(d * d, 1))
            ndot = tf.reduce_sum(d * nrm, 1)
            g = tf.where(ndot > 0, ndot / (q * tf.maximum(q * q, MIN_DISTANCE ** 2)), tf.zeros_like(q))
            e = tf.gather(col * inten[:, None], li)
            light_bytes = amb + POINT_SCALE * tf.math.unsorted_segment_sum(g[:, None] * e, pi, n)
            peak = tf.reduce_max(light_bytes, 1, keepdims=True)
            clamped = light_bytes * tf.where(peak > BYTE_MAX, BYTE_MAX / tf.maximum(peak, BYTE_MAX), tf.ones_like(peak))
            residual = albedo * LINEAR_PER_BYTE * clamped - target
            value = tf.reduce_sum(weight * residual * residual) / m.norm
        return value, tape.gradient(value, [pos, col, inten, amb])

    def call():
        value, grads = run()
        return float(value), [tf.convert_to_tensor(g).numpy() for g in grads]  # gathers give IndexedSlices

    return call


def drjit_objective(m, lights, point, light):
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    F, U = mi.Float, mi.UInt32
    n = m.point_count
    pts = [F(m.points[point, k]) for k in range(3)]
    nrm = [F(m.normals[point, k]) for k in range(3)]
    albedo = [F(m.albedo[:, k]) for k in range(3)]
    target = [F(m.radiance[:, k]) for k in range(3)]
    weight = F(m.weights)
    pi, li = U(point.astype(np.uint32)), U(light.astype(np.uint32))

    def call():
        pos = [F(lights.positions[:, k]) for k in range(3)]
        col = [F(lights.colours[:, k]) for k in range(3)]
        inten = F(lights.intensities)
        amb = [F(np.full(1, lights.ambient[k])) for k in range(3)]
        for v in (*pos, *col, inten, *amb):
            dr.enable_grad(v)
        d = [dr.gather(F, pos[k], li) - pts[k] for k in range(3)]
        q = dr.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        ndot = d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]
        g = dr.select(ndot > 0, ndot / (q * dr.maximum(q * q, MIN_DISTANCE ** 2)), 0.0)
        inten_p = dr.gather(F, inten, li)
        light_bytes = []
        for k in range(3):
            total = dr.zeros(F, n)
            dr.scatter_reduce(dr.ReduceOp.Add, total, POINT_SCALE * g * dr.gather(F, col[k], li) * inten_p, U(pi))
            light_bytes.append(total + dr.gather(F, amb[k], dr.zeros(U, n)))
        peak = dr.maximum(light_bytes[0], dr.maximum(light_bytes[1], light_bytes[2]))
        scale = dr.select(peak > BYTE_MAX, BYTE_MAX / dr.maximum(peak, BYTE_MAX), 1.0)
        value = dr.sum(sum(weight * dr.square(albedo[k] * LINEAR_PER_BYTE * light_bytes[k] * scale - target[k])
                           for k in range(3))) / m.norm
        dr.backward(value)
        grads = [np.stack([np.asarray(dr.grad(v)) for v in pos], 1), np.stack([np.asarray(dr.grad(v)) for v in col], 1),
                 np.asarray(dr.grad(inten)), np.array([np.asarray(dr.grad(v))[0] for v in amb])]
        return float(np.asarray(value)[0] if np.ndim(np.asarray(value)) else value), grads

    return call


def mitsuba_rays(vertices, triangles):
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    mesh = mi.Mesh("level", vertex_count=len(vertices), face_count=len(triangles), has_vertex_normals=False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(vertices.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(triangles.astype(np.uint32).ravel())
    params.update()
    scene = mi.load_dict({"type": "scene", "level": mesh})

    def cast(origins, directions, lengths):
        ray = mi.Ray3f(mi.Point3f(*[mi.Float(origins[:, k]) for k in range(3)]),
                       mi.Vector3f(*[mi.Float(directions[:, k]) for k in range(3)]))
        ray.maxt = mi.Float(lengths)
        hit = scene.ray_test(ray)
        dr.eval(hit)
        return np.asarray(hit)

    return cast


BACKENDS = {"tensorflow autodiff (float64)": "tensorflow_objective", "drjit llvm_ad_rgb (float32)": "drjit_objective"}


def main() -> int:
    """Each library in its own process: TensorFlow and Dr.Jit both bring an LLVM, and one process
    with both crashed here."""
    import subprocess

    level = sys.argv[1] if len(sys.argv) > 1 else "oa_dm1"
    if len(sys.argv) > 2:
        return run_part(level, sys.argv[2])
    for part in ("numpy", *BACKENDS, "rays"):
        done = subprocess.run([sys.executable, __file__, level, part], check=False)
        if done.returncode != 0:
            print(f"{part}: failed (exit code {done.returncode})")
    return 0


def run_part(name: str, part: str) -> int:
    level = load_level(name)
    scene = load_scene(level)
    m = scene.model
    lights = initial_intensity(m, initial_grid(scene.bounds[0], scene.bounds[1], DEFAULT_GRID, scene.is_open))
    lights.positions = lights.positions + 3.0  # off the grid's symmetric start
    lights.ambient = np.array([20.0, 15.0, 10.0])
    visible = m.visibility(lights)
    point, light = np.nonzero(visible)
    numpy_seconds, reference = timed(lambda: m.objective(lights, visible))
    ref = [reference.positions, reference.colours, reference.intensities, reference.ambient]
    if part == "numpy":
        print(f"{level.name}: {m.point_count:,} target points, {lights.count} lights, {len(point):,} visible pairs "
              f"({len(point) / visible.size:.1%} of all)")
        print(f"numpy analytic (float64): {numpy_seconds * 1000:7.0f} ms per objective + gradient")
    elif part in BACKENDS:
        try:
            run = globals()[BACKENDS[part]](m, lights, point, light)
        except ImportError as exc:
            print(f"{part}: not installed ({exc.name})")
            return 0
        seconds, (value, grads) = timed(run)
        worst = max(float(np.max(np.abs(g - r)) / max(float(np.max(np.abs(r))), 1e-300)) for g, r in zip(grads, ref))
        print(f"{part}: {seconds * 1000:7.0f} ms per objective + gradient (numpy in the same process "
              f"{numpy_seconds * 1000:.0f} ms); objective {value:.6f} vs {reference.value:.6f}, largest gradient "
              f"difference {worst:.1e} of the largest component")
    else:  # the shadow rays of one refresh: from every point to every light in front and in range
        origins = m.points[point] + RAY_OFFSET * m.normals[point]
        offsets = lights.positions[light] - origins
        lengths = np.linalg.norm(offsets, axis=1)
        directions = offsets / lengths[:, None]
        embree_seconds, hits = timed(lambda: m.raycaster.cast(origins, directions, float(lengths.max()))[0])
        print(f"embree (embreex, 2 threads): {len(origins) / embree_seconds:12,.0f} rays/s")
        try:
            geometry = ray_geometry(level.bsp)
            cast = mitsuba_rays(geometry.vertices, geometry.triangles)
        except ImportError as exc:
            print(f"mitsuba: not installed ({exc.name})")
            return 0
        mitsuba_seconds, blocked = timed(lambda: cast(origins, directions, lengths))
        print(f"mitsuba ray_test (llvm):     {len(origins) / mitsuba_seconds:12,.0f} rays/s; "
              f"agrees with Embree on {np.mean(blocked == (hits < lengths)):.2%} of rays")
    return 0


if __name__ == "__main__":
    sys.exit(main())
