using System;
using Lpnn.Probes.Core.Numerics;

namespace Lpnn.Probes.Core.Quality
{
    /// <summary>The placement error of a probe set (Documentation~/quality.md §1–2): every evaluation point that is not
    /// a probe is interpolated from the probes through the given tetrahedra — inside the hull from its tetrahedron,
    /// outside from the nearest point of the hull surface — and compared with its reference lighting in the 42
    /// D14 × RGB values. Probes reproduce themselves (error 0).</summary>
    public static class PlacementError
    {
        /// <param name="reference">The dense lighting of all evaluation points.</param>
        /// <param name="probes">Evaluation point indices of the probes (distinct, at least 4).</param>
        /// <param name="tetrahedra">4 indices into <paramref name="probes"/> per tetrahedron (as Unity's
        /// Lightmapping.Tetrahedralize returns them over the probe positions).</param>
        public static PlacementErrorResult Evaluate(ReferenceLighting reference, int[] probes, int[] tetrahedra)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            int count = reference.Count;
            var irradiance = new double[count];
            var smape = new double[count];
            var outside = new bool[count];
            InterpolateOthers(reference, probes, tetrahedra, (int n, ref Stencil stencil, double[] interpolated) =>
            {
                outside[n] = stencil.Outside;
                irradiance[n] = PointErrorMetrics.Irradiance(interpolated, reference.Light, n * ReferenceLighting.LightValues, reference.SceneScale);
                smape[n] = PointErrorMetrics.Smape(interpolated, reference.Light, n * ReferenceLighting.LightValues, reference.SceneScale);
            });
            int outsideCount = 0;
            foreach (bool o in outside)
                if (o) outsideCount++;
            return new PlacementErrorResult(probes.Length, outsideCount, irradiance, smape);
        }

        /// <summary>The irradiance error's mean of <see cref="Evaluate"/> (the same number), without the SMAPE and the
        /// percentiles: what the tolerance search measures at each of its probe counts.</summary>
        public static double IrradianceMean(ReferenceLighting reference, int[] probes, int[] tetrahedra)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            var irradiance = new double[reference.Count];
            InterpolateOthers(reference, probes, tetrahedra, (int n, ref Stencil stencil, double[] interpolated) =>
                irradiance[n] = PointErrorMetrics.Irradiance(interpolated, reference.Light, n * ReferenceLighting.LightValues, reference.SceneScale));
            return ErrorSummary.MeanOf(irradiance);
        }

        /// <summary>Receives one evaluation point that is not a probe: its stencil (probe-list indices, weights, cell) and
        /// its 42 interpolated values (a buffer reused for the thread's next point). Called on worker threads for several
        /// points at once (<see cref="ParallelChunks"/>), in no particular order: it may write only the point's own slots
        /// (errors[point], …), never a sum, count or list over points — those are taken after the pass on the calling
        /// thread, in ascending point order, so the answers do not depend on the thread count; and it must not call the
        /// engine (rays are cast after the pass, on the calling thread).</summary>
        internal delegate void PointVisitor(int point, ref Stencil stencil, double[] interpolated);

        /// <summary>Receives the points' stencils one after another on the calling thread, in ascending point order (the
        /// order of the points asked for), after they were computed in parallel: for lists in that order, such as the
        /// points and stencils whose segments the leak checks cast.</summary>
        internal delegate void StencilVisitor(int point, ref Stencil stencil);

        /// <summary>Interpolates every evaluation point that is not a probe through the given tetrahedra (inside: its
        /// tetrahedron; outside: the nearest hull point), visiting each once (<see cref="PointVisitor"/>: in parallel), then
        /// the stencils in ascending index order (<paramref name="inOrder"/>, optional). Shared by the error and the
        /// insertion ranking, so both read the same stencils.</summary>
        internal static void InterpolateOthers(ReferenceLighting reference, int[] probes, int[] tetrahedra, PointVisitor visit,
            StencilVisitor inOrder = null) =>
            InterpolatePoints(reference, probes, tetrahedra, null, visit, inOrder);

        /// <summary>As <see cref="InterpolateOthers"/>, but only at <paramref name="points"/> (evaluation point indices, none
        /// of them a probe; null: every point that is not a probe; <paramref name="inOrder"/> gets them in this order): batched
        /// refinement re-evaluates only the points whose stencil changed. A point's stencil does not depend on which other
        /// points are asked for. <paramref name="visit"/> null: the stencils only, nothing interpolated.</summary>
        internal static void InterpolatePoints(ReferenceLighting reference, int[] probes, int[] tetrahedra, int[] points, PointVisitor visit,
            StencilVisitor inOrder = null)
        {
            ProbeIndices.Check(probes, reference.Count);
            InterpolatePoints(reference, probes, TetrahedralMesh.Build(ProbePoints(reference, probes), tetrahedra), points, visit, inOrder);
        }

        /// <summary>As the overload, through a built <paramref name="mesh"/> of <paramref name="probes"/> (batched refinement
        /// keeps each set's mesh to derive the next one from it).</summary>
        internal static void InterpolatePoints(ReferenceLighting reference, int[] probes, TetrahedralMesh mesh, int[] points, PointVisitor visit,
            StencilVisitor inOrder = null)
        {
            var locator = new TetrahedronLocator(mesh);
            var hull = new HullProjector(mesh.Points, mesh.HullFaces, mesh.HullFaceOwners);
            Visit(reference, probes, mesh, locator, hull, points ?? Others(reference.Count, probes), visit, inOrder);
        }

        /// <summary>Points asked for per parallel pass when their stencils are also visited in order: the stencils of one
        /// pass are kept until then (~2 MB).</summary>
        private const int InOrderBlock = 32768;

        /// <summary>Locates (and with <paramref name="visit"/> interpolates and visits) <paramref name="points"/> in parallel
        /// chunks, then hands their stencils to <paramref name="inOrder"/> in the order given, a block at a time.</summary>
        private static void Visit(ReferenceLighting reference, int[] probes, TetrahedralMesh mesh, TetrahedronLocator locator,
            HullProjector hull, int[] points, PointVisitor visit, StencilVisitor inOrder)
        {
            int block = inOrder == null ? Math.Max(1, points.Length) : InOrderBlock;
            Stencil[] stencils = inOrder == null ? null : new Stencil[Math.Min(block, points.Length)];
            double[] local = reference.Local, light = reference.Light;
            for (int from = 0; from < points.Length; from += block)
            {
                int first = from, size = Math.Min(block, points.Length - from);
                ParallelChunks.For(size, (start, end) =>
                {
                    // Per chunk: the thread's scratch (the shared locator and hull are read only).
                    var weights = new double[4];
                    var interpolated = visit == null ? null : new double[ReferenceLighting.LightValues];
                    int[] stack = HullProjector.NewStack();
                    var stencil = new Stencil();
                    for (int i = start; i < end; i++)
                    {
                        int n = points[first + i];
                        Locate(mesh, locator, hull, stack, local, n, weights, ref stencil);
                        if (stencils != null) stencils[i] = stencil;
                        if (visit == null) continue;
                        Interpolate(light, probes, ref stencil, interpolated);
                        visit(n, ref stencil, interpolated);
                    }
                });
                if (inOrder == null) continue;
                for (int i = 0; i < size; i++) inOrder(points[first + i], ref stencils[i]);
            }
        }

        /// <summary>Every point index below <paramref name="count"/> that is not one of <paramref name="probes"/>, ascending.</summary>
        private static int[] Others(int count, int[] probes)
        {
            var isProbe = new bool[count];
            int distinct = 0;
            foreach (int p in probes)
            {
                if (!isProbe[p]) distinct++;
                isProbe[p] = true;
            }
            var others = new int[count - distinct];
            for (int n = 0, k = 0; n < count; n++)
                if (!isProbe[n]) others[k++] = n;
            return others;
        }

        /// <summary>As <see cref="InterpolateOthers"/> on a built <paramref name="mesh"/> of <paramref name="probes"/>, but a
        /// point whose tetrahedron is known (<paramref name="knownCell"/>[n] ≥ 0, a tetrahedron of the mesh containing it) and
        /// clearly inside it (<see cref="TetrahedronLocator.TryWeightsIn"/>) only gets its weights there, the numbers a
        /// location computes; the others (-1, or on their tetrahedron's boundary) are located as usual, after them: the same
        /// stencils. Insertion's incremental rounds (<see cref="InsertionRounds"/>). Returns how many points were located.</summary>
        internal static int InterpolateOthers(ReferenceLighting reference, int[] probes, TetrahedralMesh mesh, int[] knownCell, PointVisitor visit)
        {
            var locator = new TetrahedronLocator(mesh);
            double[] local = reference.Local, light = reference.Light;
            int[] others = Others(reference.Count, probes);
            var unknown = new bool[others.Length];
            ParallelChunks.For(others.Length, (start, end) =>
            {
                var interpolated = new double[ReferenceLighting.LightValues];
                var weights = new double[4];
                var stencil = new Stencil();
                for (int i = start; i < end; i++)
                {
                    int n = others[i], t = knownCell[n];
                    if (t < 0 || !locator.TryWeightsIn(t, local[3 * n], local[3 * n + 1], local[3 * n + 2], weights))
                    {
                        unknown[i] = true;
                        continue;
                    }
                    InsideStencil(mesh, t, weights, ref stencil);
                    Interpolate(light, probes, ref stencil, interpolated);
                    visit(n, ref stencil, interpolated);
                }
            });
            int located = 0;
            foreach (bool u in unknown)
                if (u) located++;
            if (located == 0) return 0;  // no hull needed
            var toLocate = new int[located];
            for (int i = 0, k = 0; i < others.Length; i++)
                if (unknown[i]) toLocate[k++] = others[i];
            var hull = new HullProjector(mesh.Points, mesh.HullFaces, mesh.HullFaceOwners);
            Visit(reference, probes, mesh, locator, hull, toLocate, visit, null);
            return located;
        }

        /// <summary>The stencil of one evaluation point (for inspection and tests): probe-list indices and weights.</summary>
        public static Stencil StencilOf(ReferenceLighting reference, int[] probes, int[] tetrahedra, int point)
        {
            if (reference == null) throw new ArgumentNullException(nameof(reference));
            ProbeIndices.Check(probes, reference.Count);
            if ((uint)point >= (uint)reference.Count)
                throw new ArgumentOutOfRangeException(nameof(point), point, "point index must be in 0.." + (reference.Count - 1));
            var mesh = TetrahedralMesh.Build(ProbePoints(reference, probes), tetrahedra);
            var stencil = new Stencil();
            Locate(mesh, new TetrahedronLocator(mesh), new HullProjector(mesh.Points, mesh.HullFaces, mesh.HullFaceOwners), HullProjector.NewStack(),
                reference.Local, point, new double[4], ref stencil);
            return stencil;
        }

        internal static double[] ProbePoints(ReferenceLighting reference, int[] probes)
        {
            var points = new double[3 * probes.Length];
            for (int k = 0; k < probes.Length; k++)
                Array.Copy(reference.Local, 3 * probes[k], points, 3 * k, 3);
            return points;
        }

        private static void Locate(TetrahedralMesh mesh, TetrahedronLocator locator, HullProjector hull, int[] stack, double[] local, int n,
            double[] weights, ref Stencil stencil)
        {
            double x = local[3 * n], y = local[3 * n + 1], z = local[3 * n + 2];
            if (locator.TryLocate(x, y, z, weights, out int t))
            {
                InsideStencil(mesh, t, weights, ref stencil);
                return;
            }
            int f = hull.Nearest(x, y, z, stack, out double u, out double v, out double w);
            stencil.Probe0 = mesh.HullFaces[3 * f];
            stencil.Probe1 = mesh.HullFaces[3 * f + 1];
            stencil.Probe2 = mesh.HullFaces[3 * f + 2];
            stencil.Probe3 = stencil.Probe0;
            stencil.Weight0 = u;
            stencil.Weight1 = v;
            stencil.Weight2 = w;
            stencil.Weight3 = 0;
            stencil.Outside = true;
            stencil.Cell = mesh.HullFaceOwners[f];
        }

        private static void InsideStencil(TetrahedralMesh mesh, int t, double[] weights, ref Stencil stencil)
        {
            stencil.Probe0 = mesh.Tetrahedra[4 * t];
            stencil.Probe1 = mesh.Tetrahedra[4 * t + 1];
            stencil.Probe2 = mesh.Tetrahedra[4 * t + 2];
            stencil.Probe3 = mesh.Tetrahedra[4 * t + 3];
            stencil.Weight0 = weights[0];
            stencil.Weight1 = weights[1];
            stencil.Weight2 = weights[2];
            stencil.Weight3 = weights[3];
            stencil.Outside = false;
            stencil.Cell = t;
        }

        /// <summary>Σ wₖ·E(probeₖ) over the 42 values: the SH blend is linear, so this equals evaluating the blended SH.</summary>
        private static void Interpolate(double[] light, int[] probes, ref Stencil s, double[] result)
        {
            const int values = ReferenceLighting.LightValues;
            int o0 = values * probes[s.Probe0], o1 = values * probes[s.Probe1], o2 = values * probes[s.Probe2], o3 = values * probes[s.Probe3];
            for (int i = 0; i < values; i++)
                result[i] = s.Weight0 * light[o0 + i] + s.Weight1 * light[o1 + i] + s.Weight2 * light[o2 + i] + s.Weight3 * light[o3 + i];
        }
    }
}
