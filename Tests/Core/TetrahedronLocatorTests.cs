using System;
using System.Collections.Generic;
using Lpnn.Probes.Core.Quality;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>Point location across a crack (Documentation~/quality.md §1 "Inside the hull"): a tetrahedralisation whose
    /// flat tetrahedron was dropped leaves faces no tetrahedron shares inside the hull. The Python walk used to take them for
    /// the hull and declare points beyond them outside; the locator here tests every tetrahedron of the point's bucket, so
    /// it never depended on adjacency. These cases are the Python tests' (tests/quality/test_quality_location.py), the same
    /// tetrahedra in the same order, so both languages are pinned to the same cells.</summary>
    [TestFixture]
    public class TetrahedronLocatorTests
    {
        private const int A = 0, B = 1, C = 2, D = 3, E = 4, F = 5, G = 6;

        /// <summary>A square a b c d at z = 0 between an apex e above and a pyramid below (apex f, inner vertex g).</summary>
        private static readonly double[] Points =
        {
            0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, // a b c d
            0.5, 0.5, 1,                        // e
            0.5, 0.5, -1,                       // f
            0.5, 0.5, -0.4,                     // g
        };

        /// <summary>Above, the square is cut along a–c; below, along b–d: the flat a b c d joining the sides is missing.</summary>
        private static readonly int[] Tetrahedra =
        {
            A, B, C, E, A, C, D, E,
            A, B, D, G, B, C, D, G, A, B, F, G, B, C, F, G, C, D, F, G, D, A, F, G,
        };

        private static TetrahedralMesh CrackMesh() => TetrahedralMesh.Build(Points, Tetrahedra);

        private static double[] Along(int from, int to, double t)
        {
            var p = new double[3];
            for (int axis = 0; axis < 3; axis++) p[axis] = (1 - t) * Points[3 * from + axis] + t * Points[3 * to + axis];
            return p;
        }

        /// <summary>Documentation~/quality.md §1 "Ties" over every tetrahedron: the one the point is clearly inside, else the
        /// lowest-index one it is inside within the tolerance, else −1.</summary>
        private static int Rule(TetrahedralMesh mesh, double x, double y, double z)
        {
            int lowest = -1;
            for (int t = 0; t < mesh.TetrahedronCount; t++)
            {
                double smallest = SmallestBarycentric(mesh, t, x, y, z);
                if (smallest > TetrahedronLocator.ClearlyInside) return t;
                if (lowest < 0 && smallest >= -TetrahedronLocator.InsideTolerance) lowest = t;
            }
            return lowest;
        }

        private static double SmallestBarycentric(TetrahedralMesh mesh, int t, double x, double y, double z)
        {
            double[] p = mesh.Points, m = mesh.Inverse;
            int v0 = mesh.Tetrahedra[4 * t];
            double qx = x - p[3 * v0], qy = y - p[3 * v0 + 1], qz = z - p[3 * v0 + 2];
            double l1 = m[9 * t] * qx + m[9 * t + 1] * qy + m[9 * t + 2] * qz;
            double l2 = m[9 * t + 3] * qx + m[9 * t + 4] * qy + m[9 * t + 5] * qz;
            double l3 = m[9 * t + 6] * qx + m[9 * t + 7] * qy + m[9 * t + 8] * qz;
            return Math.Min(Math.Min(1 - (l1 + l2 + l3), l1), Math.Min(l2, l3));
        }

        [Test]
        public void TheCrackFacesAreBoundaryFacesOfTheMeshAsInPython()
        {
            // The 8 sides of the two pyramids and the crack's 4 faces (Python lists them among hull_faces too; its walk
            // tells them apart as INNER_BOUNDARY).
            Assert.That(CrackMesh().HullFaceCount, Is.EqualTo(12));
        }

        [Test]
        public void APointOnAnInteriorEdgeBeyondTheCrackIsInsideWithTheLowestIndexTetrahedronOfTheEdge()
        {
            var mesh = CrackMesh();
            var locator = new TetrahedronLocator(mesh);
            double[] q = Along(G, F, 0.25);
            var weights = new double[4];
            Assert.That(locator.TryLocate(q[0], q[1], q[2], weights, out int tetrahedron), Is.True);
            Assert.That(tetrahedron, Is.EqualTo(4), "a-b-f-g, the first of the four tetrahedra around g-f");
            Assert.That(tetrahedron, Is.EqualTo(Rule(mesh, q[0], q[1], q[2])));
            var byVertex = new Dictionary<int, double>();
            for (int k = 0; k < 4; k++) byVertex[mesh.Tetrahedra[4 * tetrahedron + k]] = weights[k];
            Assert.That(byVertex[G], Is.EqualTo(0.75).Within(1e-12));
            Assert.That(byVertex[F], Is.EqualTo(0.25).Within(1e-12));
        }

        [Test]
        public void APointOnTheCrackTakesTheLowestIndexTetrahedronOfBothSides()
        {
            var mesh = CrackMesh();
            double[] q = Along(A, C, 0.25);  // in both tetrahedra above and in a-b-d-g below
            Assert.That(new TetrahedronLocator(mesh).TryLocate(q[0], q[1], q[2], new double[4], out int tetrahedron), Is.True);
            Assert.That(tetrahedron, Is.EqualTo(0));
        }

        [Test]
        public void EveryPointOfAHalfCellLatticeThroughTheMeshGetsTheRulesTetrahedron()
        {
            // Points on the crack, on its edges and on the pyramids' edges and faces, inside and outside the hull.
            var mesh = CrackMesh();
            var locator = new TetrahedronLocator(mesh);
            var weights = new double[4];
            int inside = 0, outside = 0;
            for (int i = -1; i <= 9; i++)
            for (int j = -1; j <= 9; j++)
            for (int k = -12; k <= 12; k++)
            {
                double x = i / 8.0, y = j / 8.0, z = k / 10.0;
                int expected = Rule(mesh, x, y, z);
                bool found = locator.TryLocate(x, y, z, weights, out int tetrahedron);
                Assert.That(found ? tetrahedron : -1, Is.EqualTo(expected), $"point ({x}, {y}, {z})");
                if (found) inside++;
                else outside++;
            }
            Assert.That(inside, Is.GreaterThan(0));
            Assert.That(outside, Is.GreaterThan(0));
        }
    }
}
