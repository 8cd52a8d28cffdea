using System;
using System.Linq;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The radix sort the meshes' faces are sorted by (<see cref="KeySort"/>), against LINQ's stable OrderBy; and
    /// a mesh's hull faces, whose order and owners must not depend on how the faces' keys are packed.</summary>
    [TestFixture]
    public class KeySortTests
    {
        [TestCase(1, 1000, 50L)]                 // many equal keys: the items must keep their input order
        [TestCase(2, 5000, 1L << 20)]            // two 16-bit passes
        [TestCase(3, 5000, long.MaxValue)]       // every pass, the top bit of the last one clear
        [TestCase(4, 1, 7L)]
        public void SortsAscendingAndStable(int seed, int count, long bound)
        {
            var random = new Random(seed);
            var keys = new long[count + 3];  // the last three lie beyond count: left alone
            for (int i = 0; i < keys.Length; i++) keys[i] = (long)(random.NextDouble() * bound) % bound;
            var items = Enumerable.Range(0, keys.Length).ToArray();
            var expected = Enumerable.Range(0, count).OrderBy(i => keys[i]).ToArray();  // stable
            long[] tail = keys.Skip(count).ToArray();
            long[] original = (long[])keys.Clone();
            KeySort.Sort(keys, items, count);
            Assert.That(items.Take(count), Is.EqualTo(expected));
            Assert.That(keys.Take(count), Is.EqualTo(expected.Select(i => original[i])));
            Assert.That(keys.Skip(count), Is.EqualTo(tail));
            Assert.That(items.Skip(count), Is.EqualTo(new[] { count, count + 1, count + 2 }));
        }

        [Test]
        public void RefusesNegativeKeys()
        {
            var error = Assert.Throws<ArgumentOutOfRangeException>(() => KeySort.Sort(new[] { 3L, -1L }, null, 2));
            StringAssert.Contains("negative", error.Message);
        }

        /// <summary>Two tetrahedra sharing a face: six hull faces, ascending by sorted corners, each owned by its tetrahedron,
        /// whether the probe indices are small (three corners packed in one key) or beyond 2^21 (sorted by two keys).</summary>
        [Test]
        public void HullFacesDoNotDependOnTheKeysPacking()
        {
            int[] small = { 0, 1, 2, 3, 4 };
            int[] large = { 5, 2200000, 2200001, 2300000, 2400000 };  // the same order: the same hull, relabelled
            var smallHull = HullWith(small, 5, out int[] smallOwners);
            var largeHull = HullWith(large, 2400001, out int[] largeOwners);
            Assert.That(smallHull.Length, Is.EqualTo(18), "six hull faces");
            Assert.That(largeHull.Select(v => Array.IndexOf(large, v)), Is.EqualTo(smallHull));
            Assert.That(largeOwners, Is.EqualTo(smallOwners));
            // Ascending by sorted corners, as the faces' order was before the keys were packed.
            var faces = Enumerable.Range(0, 6).Select(f => Tuple.Create(smallHull[3 * f], smallHull[3 * f + 1], smallHull[3 * f + 2])).ToArray();
            Assert.That(faces, Is.EqualTo(faces.OrderBy(f => f.Item1).ThenBy(f => f.Item2).ThenBy(f => f.Item3)));
            Assert.That(smallOwners, Is.EqualTo(new[] { 0, 0, 0, 1, 1, 1 }));
        }

        /// <summary>The hull of tetrahedra (0, 1, 2, 3) and (1, 2, 3, 4) over a double pyramid, the five corners at
        /// <paramref name="index"/> among <paramref name="probes"/> probes (the rest at the origin, unused).</summary>
        private static int[] HullWith(int[] index, int probes, out int[] owners)
        {
            double[][] corners = { new[] { 0.0, 0, -1 }, new[] { 1.0, 0, 0 }, new[] { 0.0, 1, 0 }, new[] { -1.0, -1, 0 }, new[] { 0.0, 0, 1 } };
            var points = new double[3 * probes];
            for (int k = 0; k < 5; k++) Array.Copy(corners[k], 0, points, 3 * index[k], 3);
            var mesh = TetrahedralMesh.Build(points, new[] { index[0], index[1], index[2], index[3], index[1], index[2], index[3], index[4] });
            owners = mesh.HullFaceOwners;
            return mesh.HullFaces;
        }
    }
}
