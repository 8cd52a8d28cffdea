using System;
using System.Globalization;
using System.Linq;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The tie rule's numbering of tetrahedra (TetrahedronNumbering; Documentation~/quality.md §1 "Ties") against
    /// Tests/Data/tet_numbering_golden.json (written by Tools~/golden/make_tet_numbering_golden.py in plain integers, not by
    /// this code; Python's test_quality_tet_numbering.py reads it too), splitmix64's published outputs, and its
    /// independence of the order the tetrahedra and their corners come in.</summary>
    [TestFixture]
    public class TetrahedronNumberingTests
    {
        [Test]
        public void TheMixerIsSplitmix64()
        {
            // splitmix64 seeded with 1234567 (Vigna's reference generator, prng.di.unimi.it/splitmix64.c): state += gamma,
            // output = the finaliser of the state. Its first outputs, as published with the generator.
            ulong[] published = { 6457827717110365317UL, 3203168211198807973UL, 9817491932198370423UL, 4593380528125082431UL, 16408922859458223821UL };
            ulong state = 1234567UL;
            foreach (ulong expected in published)
            {
                state = unchecked(state + TetrahedronNumbering.GoldenGamma);
                Assert.That(TetrahedronNumbering.Mix64(state), Is.EqualTo(expected));
            }
        }

        [Test]
        public void TheGoldenTetrahedraAreNumberedAsWritten()
        {
            var golden = TestData.ReadJson("tet_numbering_golden.json");
            int[] ids = golden.Get("ids").Items.Select(v => (int)v.AsNumber).ToArray();
            int[] tetrahedra = golden.Get("tetrahedra").Items.SelectMany(t => t.Items.Select(v => (int)v.AsNumber)).ToArray();
            int[] expected = golden.Get("numbered").Items.SelectMany(t => t.Items.Select(v => (int)v.AsNumber)).ToArray();
            int[] numbered = TetrahedronNumbering.Numbered(tetrahedra, ids);
            Assert.That(numbered, Is.EqualTo(expected));
            var hashes = golden.Get("hashes").Items.Select(v => ulong.Parse(v.AsString.Substring(2), NumberStyles.HexNumber, CultureInfo.InvariantCulture)).ToArray();
            for (int t = 0; t < hashes.Length; t++)
                Assert.That(TetrahedronNumbering.Hash(ids[numbered[4 * t]], ids[numbered[4 * t + 1]], ids[numbered[4 * t + 2]], ids[numbered[4 * t + 3]]),
                    Is.EqualTo(hashes[t]), "tetrahedron " + t);
        }

        [Test]
        public void TheNumberingIsAFunctionOfTheSetOfTetrahedraOnly()
        {
            var golden = TestData.ReadJson("tet_numbering_golden.json");
            int[] ids = golden.Get("ids").Items.Select(v => (int)v.AsNumber).ToArray();
            int[][] tetrahedra = golden.Get("tetrahedra").Items.Select(t => t.Items.Select(v => (int)v.AsNumber).ToArray()).ToArray();
            int[] expected = TetrahedronNumbering.Numbered(tetrahedra.SelectMany(t => t).ToArray(), ids);
            var random = new Random(7);
            for (int trial = 0; trial < 20; trial++)
            {
                // The tetrahedra in another order, each with its corners rotated: the same numbering.
                int[] shuffled = tetrahedra.OrderBy(_ => random.Next()).SelectMany(t =>
                {
                    int r = random.Next(4);
                    return new[] { t[r], t[(r + 1) % 4], t[(r + 2) % 4], t[(r + 3) % 4] };
                }).ToArray();
                Assert.That(TetrahedronNumbering.Numbered(shuffled, ids), Is.EqualTo(expected));
                // The probes listed in another order (positions permuted, ids with them): the same tetrahedra of point indices.
                int[] permutation = Enumerable.Range(0, ids.Length).OrderBy(_ => random.Next()).ToArray();  // old position -> new
                var movedIds = new int[ids.Length];
                for (int p = 0; p < ids.Length; p++) movedIds[permutation[p]] = ids[p];
                int[] moved = TetrahedronNumbering.Numbered(shuffled.Select(p => permutation[p]).ToArray(), movedIds);
                Assert.That(moved.Select(p => movedIds[p]), Is.EqualTo(expected.Select(p => ids[p])));
            }
        }
    }
}
