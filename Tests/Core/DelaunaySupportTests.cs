using System;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The test-only tetrahedraliser must itself be right, or every test built on it proves nothing: its output
    /// is checked against the definition of a Delaunay tetrahedralisation.</summary>
    [TestFixture]
    public class DelaunaySupportTests
    {
        [TestCase(5, 40)]
        [TestCase(6, 150)]
        [TestCase(7, 300)]
        public void OutputIsAConvexConformingDelaunayTetrahedralisation(int seed, int count)
        {
            var random = new Random(seed);
            var points = new double[count, 3];
            var positions = new Vector3[count];
            for (int n = 0; n < count; n++)
            {
                // Jittered lattice points: nearly cospherical and nearly coplanar on the box faces, the hard case for hulls.
                positions[n] = new Vector3(n % 7 + (float)(random.NextDouble() * 0.2 - 0.1), n / 7 % 6 + (float)(random.NextDouble() * 0.2 - 0.1),
                                           n / 42 + (float)(random.NextDouble() * 0.2 - 0.1));
                points[n, 0] = positions[n].X;
                points[n, 1] = positions[n].Y;
                points[n, 2] = positions[n].Z;
            }
            int[] tets = new BowyerWatsonDelaunay().Tetrahedralize(positions);
            Assert.That(tets.Length % 4, Is.EqualTo(0));
            Assert.That(tets.Distinct().Count(), Is.EqualTo(count), "every point is a vertex");
            double volume = 0;
            for (int t = 0; t < tets.Length; t += 4)
            {
                double v = BowyerWatsonDelaunay.Orient(points, tets[t], tets[t + 1], tets[t + 2], tets[t + 3]);
                Assert.That(v, Is.GreaterThan(0), "tetrahedron " + t / 4 + " is positively oriented");
                volume += v / 6;
                for (int p = 0; p < count; p++)
                    Assert.That(BowyerWatsonDelaunay.InSphere(points, tets[t], tets[t + 1], tets[t + 2], tets[t + 3], p), Is.LessThanOrEqualTo(1e-9),
                        "point " + p + " inside the circumsphere of tetrahedron " + t / 4);
            }
            // The boundary is convex: every point lies on the inner side of every hull triangle, so the union of the
            // tetrahedra is the convex hull (no missing hull slivers).
            var hull = HullFaces.Of(tets);
            foreach (var face in hull)
            {
                int owner = -1;
                for (int t = 0; t < tets.Length && owner < 0; t += 4)
                    if (face.All(v => Array.IndexOf(tets, v, t, 4) >= 0)) owner = t;
                int inner = tets.Skip(owner).Take(4).First(v => !face.Contains(v));
                double side = BowyerWatsonDelaunay.Orient(points, face[0], face[1], face[2], inner);
                for (int p = 0; p < count; p++)
                    Assert.That(BowyerWatsonDelaunay.Orient(points, face[0], face[1], face[2], p) * Math.Sign(side), Is.GreaterThanOrEqualTo(-1e-9), "hull is convex");
            }
            Assert.That(volume, Is.GreaterThan(0));
            Assert.That(hull.Count, Is.GreaterThanOrEqualTo(4));
        }

        [Test]
        public void CoplanarPointsAreRefused()
        {
            var flat = new[] { new Vector3(0, 0, 0), new Vector3(1, 0, 0), new Vector3(0, 1, 0), new Vector3(1, 1, 0), new Vector3(2, 3, 0) };
            Assert.Throws<ArgumentException>(() => new BowyerWatsonDelaunay().Tetrahedralize(flat));
        }
    }
}
