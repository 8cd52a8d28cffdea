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
            int outside = 0;
            InterpolateOthers(reference, probes, tetrahedra, (int n, ref Stencil stencil, double[] interpolated) =>
            {
                if (stencil.Outside) outside++;
                irradiance[n] = PointErrorMetrics.Irradiance(interpolated, reference.Light, n * ReferenceLighting.LightValues, reference.SceneScale);
                smape[n] = PointErrorMetrics.Smape(interpolated, reference.Light, n * ReferenceLighting.LightValues, reference.SceneScale);
            });
            return new PlacementErrorResult(probes.Length, outside, irradiance, smape);
        }

        /// <summary>Receives one evaluation point that is not a probe: its stencil (probe-list indices, weights, cell) and
        /// its 42 interpolated values (a buffer reused for the next point).</summary>
        internal delegate void PointVisitor(int point, ref Stencil stencil, double[] interpolated);

        /// <summary>Interpolates every evaluation point that is not a probe, in ascending index order, through the given
        /// tetrahedra (inside: its tetrahedron; outside: the nearest hull point). Shared by the error and the insertion
        /// ranking, so both read the same stencils.</summary>
        internal static void InterpolateOthers(ReferenceLighting reference, int[] probes, int[] tetrahedra, PointVisitor visit) =>
            InterpolatePoints(reference, probes, tetrahedra, null, visit);

        /// <summary>As <see cref="InterpolateOthers"/>, but only at <paramref name="points"/> (evaluation point indices, none
        /// of them a probe; null: every point that is not a probe): batched refinement re-evaluates only the points whose
        /// stencil changed. A point's stencil does not depend on which other points are asked for.</summary>
        internal static void InterpolatePoints(ReferenceLighting reference, int[] probes, int[] tetrahedra, int[] points, PointVisitor visit)
        {
            ProbeIndices.Check(probes, reference.Count);
            InterpolatePoints(reference, probes, TetrahedralMesh.Build(ProbePoints(reference, probes), tetrahedra), points, visit);
        }

        /// <summary>As the overload, through a built <paramref name="mesh"/> of <paramref name="probes"/> (batched refinement
        /// keeps each set's mesh to derive the next one from it).</summary>
        internal static void InterpolatePoints(ReferenceLighting reference, int[] probes, TetrahedralMesh mesh, int[] points, PointVisitor visit)
        {
            var locator = new TetrahedronLocator(mesh);
            var hull = new HullProjector(mesh.Points, mesh.HullFaces, mesh.HullFaceOwners);

            var interpolated = new double[ReferenceLighting.LightValues];
            var weights = new double[4];
            var stencil = new Stencil();
            if (points != null)
            {
                foreach (int n in points)
                {
                    Locate(mesh, locator, hull, reference.Local, n, weights, ref stencil);
                    Interpolate(reference.Light, probes, ref stencil, interpolated);
                    visit(n, ref stencil, interpolated);
                }
                return;
            }
            int count = reference.Count;
            var isProbe = new bool[count];
            foreach (int p in probes) isProbe[p] = true;
            for (int n = 0; n < count; n++)
            {
                if (isProbe[n]) continue;
                Locate(mesh, locator, hull, reference.Local, n, weights, ref stencil);
                Interpolate(reference.Light, probes, ref stencil, interpolated);
                visit(n, ref stencil, interpolated);
            }
        }

        /// <summary>As <see cref="InterpolateOthers"/> on a built <paramref name="mesh"/> of <paramref name="probes"/>, but a
        /// point whose tetrahedron is known (<paramref name="knownCell"/>[n] ≥ 0, a tetrahedron of the mesh containing it) and
        /// clearly inside it (<see cref="TetrahedronLocator.TryWeightsIn"/>) only gets its weights there, the numbers a
        /// location computes; the others (-1, or on their tetrahedron's boundary) are located as usual: the same stencils.
        /// Insertion's incremental rounds (<see cref="InsertionRounds"/>). Returns how many points were located.</summary>
        internal static int InterpolateOthers(ReferenceLighting reference, int[] probes, TetrahedralMesh mesh, int[] knownCell, PointVisitor visit)
        {
            var locator = new TetrahedronLocator(mesh);
            HullProjector hull = null;  // built when a point is outside
            var interpolated = new double[ReferenceLighting.LightValues];
            var weights = new double[4];
            var stencil = new Stencil();
            double[] local = reference.Local;
            int count = reference.Count;
            var isProbe = new bool[count];
            foreach (int p in probes) isProbe[p] = true;
            int located = 0;
            for (int n = 0; n < count; n++)
            {
                if (isProbe[n]) continue;
                int t = knownCell[n];
                if (t >= 0 && locator.TryWeightsIn(t, local[3 * n], local[3 * n + 1], local[3 * n + 2], weights))
                    InsideStencil(mesh, t, weights, ref stencil);
                else
                {
                    if (hull == null) hull = new HullProjector(mesh.Points, mesh.HullFaces, mesh.HullFaceOwners);
                    Locate(mesh, locator, hull, local, n, weights, ref stencil);
                    located++;
                }
                Interpolate(reference.Light, probes, ref stencil, interpolated);
                visit(n, ref stencil, interpolated);
            }
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
            Locate(mesh, new TetrahedronLocator(mesh), new HullProjector(mesh.Points, mesh.HullFaces, mesh.HullFaceOwners), reference.Local, point, new double[4], ref stencil);
            return stencil;
        }

        internal static double[] ProbePoints(ReferenceLighting reference, int[] probes)
        {
            var points = new double[3 * probes.Length];
            for (int k = 0; k < probes.Length; k++)
                Array.Copy(reference.Local, 3 * probes[k], points, 3 * k, 3);
            return points;
        }

        private static void Locate(TetrahedralMesh mesh, TetrahedronLocator locator, HullProjector hull, double[] local, int n,
            double[] weights, ref Stencil stencil)
        {
            double x = local[3 * n], y = local[3 * n + 1], z = local[3 * n + 2];
            if (locator.TryLocate(x, y, z, weights, out int t))
            {
                InsideStencil(mesh, t, weights, ref stencil);
                return;
            }
            int f = hull.Nearest(x, y, z, out double u, out double v, out double w);
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
