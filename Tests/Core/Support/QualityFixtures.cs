using System;
using System.Collections.Generic;
using System.Numerics;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Sh;

namespace Lpnn.Probes.Core.Tests.Support
{
    /// <summary>Grids, lighting fields and tetrahedra for the placement-error, spread and tolerance tests.</summary>
    public static class QualityFixtures
    {
        /// <summary>An axis-aligned box grid of nx × ny × nz points with its lowest point at <paramref name="origin"/>.</summary>
        public static EvaluationGrid Box(int nx, int ny, int nz, double cell = 1, Double3 origin = default)
        {
            var max = origin + new Double3((nx - 1) * cell, (ny - 1) * cell, (nz - 1) * cell);
            return GridBuilder.Build(new[] { GridBox.AxisAligned(origin, max) }, cell);
        }

        public static Vector3[] Positions(EvaluationGrid grid)
        {
            var positions = new Vector3[grid.Count];
            for (int n = 0; n < grid.Count; n++) positions[n] = grid.GetPosition(n);
            return positions;
        }

        /// <summary>Positions moved by a deterministic random amount of up to <paramref name="amount"/> per axis (general
        /// position: a unique Delaunay tetrahedralisation).</summary>
        public static Vector3[] Jittered(Vector3[] positions, float amount, int seed)
        {
            var random = new Random(seed);
            var result = new Vector3[positions.Length];
            for (int n = 0; n < positions.Length; n++)
                result[n] = positions[n] + new Vector3((float)((random.NextDouble() * 2 - 1) * amount), (float)((random.NextDouble() * 2 - 1) * amount),
                                                       (float)((random.NextDouble() * 2 - 1) * amount));
            return result;
        }

        /// <summary>SH whose every coefficient is an affine function of the position: probe interpolation reproduces it
        /// exactly inside a tetrahedron (barycentric weights have linear precision).</summary>
        public static float[] LinearField(IReadOnlyList<Vector3> positions, Vector3 origin)
        {
            var sh = new float[ShMath.FloatsPerProbe * positions.Count];
            for (int n = 0; n < positions.Count; n++)
            {
                // Small integers × dyadic coordinates keep the float32 coefficients exact, so the field is exactly affine.
                var p = positions[n] - origin;
                for (int c = 0; c < ShMath.FloatsPerProbe; c++)
                    sh[ShMath.FloatsPerProbe * n + c] = (c % 9 == 0 ? 4f : 0.25f) + 0.25f * ((c % 3) + 1) * p.X - 0.125f * (c % 5) * p.Y + 0.0625f * (c % 7) * p.Z;
            }
            return sh;
        }

        /// <summary>A smooth, clearly non-linear field: a base light plus two coloured Gaussian blobs.</summary>
        public static float[] BlobField(IReadOnlyList<Vector3> positions, Vector3 centreA, Vector3 centreB, float sigma)
        {
            var sh = new float[ShMath.FloatsPerProbe * positions.Count];
            var probe = new ShL2();
            for (int n = 0; n < positions.Count; n++)
            {
                var p = positions[n];
                float a = (float)Math.Exp(-(p - centreA).LengthSquared() / (sigma * sigma));
                float b = (float)Math.Exp(-(p - centreB).LengthSquared() / (sigma * sigma));
                probe = new ShL2();
                probe.AddAmbientLight(new Vector3(0.05f, 0.05f, 0.06f));
                probe.AddDirectionalLight(Vector3.Normalize(new Vector3(0.3f, 1, 0.2f)), new Vector3(1.0f, 0.6f, 0.2f), 1.5f * a);
                probe.AddDirectionalLight(Vector3.Normalize(new Vector3(-1, -0.2f, 0.5f)), new Vector3(0.2f, 0.4f, 1.0f), 2.0f * b);
                probe.CopyTo(sh, ShMath.FloatsPerProbe * n);
            }
            return sh;
        }

        /// <summary>Freudenthal–Kuhn tetrahedra of a lattice of nx × ny × nz probes listed x fastest: 6 per cube, all around
        /// its main diagonal, so neighbouring cubes share faces exactly (a conforming tetrahedralisation).</summary>
        public static int[] KuhnTetrahedra(int nx, int ny, int nz)
        {
            int[][] paths = { new[] { 0, 1, 2 }, new[] { 0, 2, 1 }, new[] { 1, 0, 2 }, new[] { 1, 2, 0 }, new[] { 2, 0, 1 }, new[] { 2, 1, 0 } };
            var tets = new List<int>();
            for (int k = 0; k + 1 < nz; k++)
            for (int j = 0; j + 1 < ny; j++)
            for (int i = 0; i + 1 < nx; i++)
            {
                foreach (var path in paths)
                {
                    int[] at = { i, j, k };
                    tets.Add(Index(at, nx, ny));
                    foreach (int axis in path)
                    {
                        at[axis]++;
                        tets.Add(Index(at, nx, ny));
                    }
                }
            }
            return tets.ToArray();
        }

        private static int Index(int[] at, int nx, int ny) => (at[2] * ny + at[1]) * nx + at[0];

        /// <summary>Grid point indices whose lattice id is a multiple of <paramref name="stride"/> on every axis (from the
        /// lowest id), listed in grid order (x fastest) — the probe order <see cref="KuhnTetrahedra"/> expects.</summary>
        public static int[] LatticeProbes(EvaluationGrid grid, int stride)
        {
            int minI = int.MaxValue, minJ = int.MaxValue, minK = int.MaxValue;
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                minI = Math.Min(minI, id.I);
                minJ = Math.Min(minJ, id.J);
                minK = Math.Min(minK, id.K);
            }
            var probes = new List<int>();
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                if ((id.I - minI) % stride == 0 && (id.J - minJ) % stride == 0 && (id.K - minK) % stride == 0) probes.Add(n);
            }
            return probes.ToArray();
        }

        public static float[] Scaled(float[] sh, float factor)
        {
            var result = new float[sh.Length];
            for (int c = 0; c < sh.Length; c++) result[c] = sh[c] * factor;
            return result;
        }
    }
}
