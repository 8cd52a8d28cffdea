using System;
using System.Diagnostics;
using System.Linq;
using System.Numerics;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Quality;
using Lpnn.Probes.Core.Sh;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The placement error of Documentation~/quality.md §1–2: interpolation inside (containing tetrahedron) and
    /// outside (nearest hull point), both metrics, the summary, and every rejected input.</summary>
    [TestFixture]
    public class PlacementErrorTests
    {
        /// <summary>7³ points, probes on every second lattice point (4³) with Kuhn tetrahedra: the hull covers the grid.</summary>
        private static void LatticeSetup(EvaluationGrid grid, int stride, out int[] probes, out int[] tets)
        {
            probes = QualityFixtures.LatticeProbes(grid, stride);
            int side = (int)Math.Round(Math.Pow(probes.Length, 1.0 / 3));
            tets = QualityFixtures.KuhnTetrahedra(side, side, side);
        }

        /// <summary>The 42 values of one probe's SH, straight from the formula of sh.md (double).</summary>
        private static double[] Light(float[] sh, int point)
        {
            var values = new double[42];
            for (int d = 0; d < 14; d++)
            {
                ShMath.Evaluate(sh, 27 * point, DirectionSets.D14[d, 0], DirectionSets.D14[d, 1], DirectionSets.D14[d, 2], out double r, out double g, out double b);
                values[3 * d] = r;
                values[3 * d + 1] = g;
                values[3 * d + 2] = b;
            }
            return values;
        }

        private static double ExpectedIrradiance(double[] x, double[] y, double scale)
        {
            double num = 0, den = 0;
            for (int i = 0; i < 42; i++)
            {
                num += Math.Abs(x[i] - y[i]);
                den += Math.Abs(x[i]) + Math.Abs(y[i]);
            }
            return num / (den + 42 * 0.01 * scale);
        }

        private static double ExpectedSmape(double[] x, double[] y, double scale)
        {
            double sum = 0;
            for (int d = 0; d < 14; d++)
            {
                double[] a = YCoCg(x, d), b = YCoCg(y, d);
                for (int c = 0; c < 3; c++) sum += Math.Abs(a[c] - b[c]) / (Math.Abs(a[c]) + Math.Abs(b[c]) + 0.01 * scale);
            }
            return sum / 42;
        }

        private static double[] YCoCg(double[] rgb, int d)
        {
            double r = rgb[3 * d], g = rgb[3 * d + 1], b = rgb[3 * d + 2];
            return new[] { r / 4 + g / 2 + b / 4, r / 2 - b / 2, -r / 4 + g / 2 - b / 4 };
        }

        [Test]
        public void AOneCellTetrahedronOfAVolumeOneHundredThousandCellsLongIsNotFlat()
        {
            // Local frame of extent 1: the probes' tetrahedron has 6 × volume 1e-15, below the old absolute 1e-14.
            var positions = new[]
            {
                new Vector3(0, 0, 0), new Vector3(1, 0, 0), new Vector3(0, 1, 0), new Vector3(0, 0, 1),
                new Vector3(0.2f, 0.2f, 0.2f), new Vector3(100000, 0, 0),
            };
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));
            var result = PlacementError.Evaluate(reference, new[] { 0, 1, 2, 3 }, new[] { 0, 1, 2, 3 });
            Assert.That(result.OutsidePoints, Is.EqualTo(1));
            Assert.That(result.PointIrradiance[4], Is.LessThan(1e-6)); // interpolated inside (float32 SH: ~3e-8)
        }

        [Test]
        public void ALinearFieldIsReproducedExactlyInsideTheHull()
        {
            var grid = QualityFixtures.Box(7, 7, 7, 0.5);
            var positions = QualityFixtures.Positions(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));
            LatticeSetup(grid, 2, out int[] probes, out int[] tets);
            var result = PlacementError.Evaluate(reference, probes, tets);
            Assert.That(result.OutsidePoints, Is.EqualTo(0));
            Assert.That(result.ProbeCount, Is.EqualTo(64));
            Assert.That(result.PointIrradiance.Max(), Is.LessThan(1e-12));
            Assert.That(result.PointSmape.Max(), Is.LessThan(1e-12));
            // A non-linear field is not reproduced: the same test with blobs must see an error (the test can fail).
            var blobs = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(2.5f, 2, 1.5f), 0.8f));
            Assert.That(PlacementError.Evaluate(blobs, probes, tets).Irradiance.Mean, Is.GreaterThan(1e-3));
        }

        [Test]
        public void OutsidePointsTakeTheValueOfTheirNearestHullPoint()
        {
            // Probes span the box [1, 3] × [1, 3] × [1, 2] of a 0..4 × 0..3.5 × 0..3 grid (cell 0.5). For an affine field,
            // interpolation on the hull surface is exact, so a point outside must get the field at its projection on the
            // box: the clamped position. Its error is then known in closed form.
            var grid = QualityFixtures.Box(9, 8, 7, 0.5);
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.LinearField(positions, Vector3.Zero);
            var reference = ReferenceLighting.Create(positions, sh, 2.0);
            var probeList = Enumerable.Range(0, grid.Count).Where(n =>
            {
                var id = grid.GetId(n);
                return id.I >= 2 && id.I <= 6 && id.I % 2 == 0 && id.J >= 2 && id.J <= 6 && id.J % 2 == 0 && id.K >= 2 && id.K <= 4 && id.K % 2 == 0;
            }).ToArray();
            int[] tets = QualityFixtures.KuhnTetrahedra(3, 3, 2);
            var result = PlacementError.Evaluate(reference, probeList, tets);
            int outside = 0;
            for (int n = 0; n < grid.Count; n++)
            {
                var p = positions[n];
                var clamped = Vector3.Clamp(p, new Vector3(1, 1, 1), new Vector3(3, 3, 2));
                if (clamped != p) outside++;
                var atClamp = QualityFixtures.LinearField(new[] { clamped }, Vector3.Zero);
                double[] interpolated = Light(atClamp, 0), exact = Light(sh, n);
                Assert.That(result.PointIrradiance[n], Is.EqualTo(ExpectedIrradiance(interpolated, exact, 2.0)).Within(1e-12), "irradiance at point " + n);
                Assert.That(result.PointSmape[n], Is.EqualTo(ExpectedSmape(interpolated, exact, 2.0)).Within(1e-12), "smape at point " + n);
            }
            Assert.That(result.OutsidePoints, Is.EqualTo(outside));
            Assert.That(outside, Is.GreaterThan(300), "most points are outside this hull");
            Assert.That(result.Irradiance.Mean, Is.GreaterThan(0.01));
            // The tolerance search's mean alone (no SMAPE, no percentile) is the same number, to the last bit.
            Assert.That(PlacementError.IrradianceMean(reference, probeList, tets), Is.EqualTo(result.Irradiance.Mean));
        }

        [Test]
        public void TheMeanAloneIsTheSummarysMean()
        {
            var values = new[] { 0.3, 1e-17, 0.1, 0.2, 1e-17, 0.0 };
            Assert.That(ErrorSummary.MeanOf(values), Is.EqualTo(ErrorSummary.Of(values).Mean));
            Assert.That(ErrorSummary.MeanOf(new[] { 1e16, 1.0, -1e16 }), Is.EqualTo(1.0 / 3), "compensated, as the summary's");
            var error = Assert.Throws<PlacementErrorException>(() => ErrorSummary.MeanOf(new double[0]));
            StringAssert.Contains("empty grid", error.Message);
        }

        [Test]
        public void StencilsHaveLinearPrecisionInsideAndProjectOntoTheNearestHullTriangleOutside()
        {
            var grid = QualityFixtures.Box(7, 6, 5, 1);
            var positions = QualityFixtures.Jittered(QualityFixtures.Positions(grid), 0.2f, 11);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(2, 2, 2), new Vector3(5, 3, 1), 1.5f));
            var random = new Random(12);
            int[] probes = Enumerable.Range(0, grid.Count).Where(n => random.NextDouble() < 0.25).ToArray();
            int[] tets = new BowyerWatsonDelaunay().Tetrahedralize(probes.Select(p => positions[p]).ToArray());
            var hull = HullFaces.Of(tets);
            int inside = 0, outside = 0;
            for (int n = 0; n < grid.Count; n++)
            {
                if (Array.IndexOf(probes, n) >= 0) continue;
                var s = PlacementError.StencilOf(reference, probes, tets, n);
                double[] w = { s.Weight0, s.Weight1, s.Weight2, s.Weight3 };
                int[] v = { s.Probe0, s.Probe1, s.Probe2, s.Probe3 };
                Assert.That(w.All(x => x >= 0), "weights ≥ 0 at point " + n);
                Assert.That(w.Sum(), Is.EqualTo(1.0).Within(1e-12));
                var anchor = Vector3.Zero;
                for (int k = 0; k < 4; k++) anchor += (float)w[k] * positions[probes[v[k]]];
                if (!s.Outside)
                {
                    inside++;
                    Assert.That((anchor - positions[n]).Length(), Is.LessThan(1e-5), "barycentric weights reproduce point " + n);
                    continue;
                }
                outside++;
                Assert.That(s.Weight3, Is.EqualTo(0.0));
                double nearest = hull.Min(f => HullFaces.DistanceToTriangle(positions[n], positions[probes[f[0]]], positions[probes[f[1]]], positions[probes[f[2]]]));
                Assert.That((anchor - positions[n]).Length(), Is.EqualTo(nearest).Within(1e-5), "point " + n + " projects onto the nearest hull point");
            }
            Assert.That(inside, Is.GreaterThan(20));
            Assert.That(outside, Is.GreaterThan(20));
        }

        [Test]
        public void MetricsFollowTheFormulasAndProbesCountAsZero()
        {
            var grid = QualityFixtures.Box(5, 5, 4, 1);
            var positions = QualityFixtures.Jittered(QualityFixtures.Positions(grid), 0.15f, 21);
            var sh = QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(3, 3, 2), 1.2f);
            var reference = ReferenceLighting.Create(positions, sh);
            Assert.That(reference.SceneScale, Is.EqualTo(SceneScale.Compute(sh, grid.Count)));
            int[] probes = { 0, 4, 20, 24, 80, 84, 99, 95, 42, 57 };
            int[] tets = new BowyerWatsonDelaunay().Tetrahedralize(probes.Select(p => positions[p]).ToArray());
            var result = PlacementError.Evaluate(reference, probes, tets);
            for (int n = 0; n < grid.Count; n++)
            {
                if (probes.Contains(n))
                {
                    Assert.That(result.PointIrradiance[n], Is.EqualTo(0.0));
                    Assert.That(result.PointSmape[n], Is.EqualTo(0.0));
                    continue;
                }
                var s = PlacementError.StencilOf(reference, probes, tets, n);
                var interpolated = new double[42];
                double[] w = { s.Weight0, s.Weight1, s.Weight2, s.Weight3 };
                int[] v = { s.Probe0, s.Probe1, s.Probe2, s.Probe3 };
                for (int k = 0; k < 4; k++)
                {
                    double[] light = Light(sh, probes[v[k]]);
                    for (int i = 0; i < 42; i++) interpolated[i] += w[k] * light[i];
                }
                Assert.That(result.PointIrradiance[n], Is.EqualTo(ExpectedIrradiance(interpolated, Light(sh, n), reference.SceneScale)).Within(1e-13));
                Assert.That(result.PointSmape[n], Is.EqualTo(ExpectedSmape(interpolated, Light(sh, n), reference.SceneScale)).Within(1e-13));
                Assert.That(result.PointIrradiance[n], Is.InRange(0.0, 1.0));
                Assert.That(result.PointSmape[n], Is.InRange(0.0, 1.0));
            }
            Assert.That(result.Irradiance.Mean, Is.EqualTo(result.PointIrradiance.Sum() / grid.Count).Within(1e-15));
            Assert.That(result.Irradiance.P95, Is.EqualTo(ErrorSummary.Percentile(result.PointIrradiance.OrderBy(e => e).ToArray(), 95)));
            Assert.That(result.Irradiance.Mean, Is.GreaterThan(0));
        }

        [TestCase(new[] { 5.0 }, 5.0)]
        [TestCase(new[] { 0.0, 1.0 }, 0.95)]
        [TestCase(new[] { 3.0, 1.0, 2.0 }, 2.9)]
        [TestCase(new[] { 0.1, 0.7, 0.2, 0.9, 0.3 }, 0.86)]
        [TestCase(new[] { 1.0, 2, 3, 4, 5, 6, 7, 8, 9, 10 }, 9.549999999999999)]
        public void ThePercentileIsNumpysLinearOne(double[] values, double expected)
        {
            // Expected values printed by numpy 2.4 (np.percentile(values, 95.0)), compared bit for bit.
            Assert.That(ErrorSummary.Of(values).P95, Is.EqualTo(expected));
        }

        [Test]
        public void ThePercentileMatchesNumpyToTheLastBitNearTheTop()
        {
            var nineteenZeros = Enumerable.Repeat(0.0, 19).Concat(new[] { 1.0 }).ToArray();
            Assert.That(ErrorSummary.Of(nineteenZeros).P95, Is.EqualTo(0.05000000000000071));
            Assert.That(ErrorSummary.Of(Enumerable.Repeat(0.0, 20).Concat(new[] { 1.0 }).ToArray()).P95, Is.EqualTo(0.0));
            Assert.That(ErrorSummary.Of(Enumerable.Range(0, 21).Select(i => (double)i).ToArray()).P95, Is.EqualTo(19.0));
            Assert.Throws<PlacementErrorException>(() => ErrorSummary.Of(new double[0]));
        }

        [Test]
        public void AnAllBlackSceneHasNoError()
        {
            var grid = QualityFixtures.Box(4, 4, 4, 1);
            var positions = QualityFixtures.Positions(grid);
            var reference = ReferenceLighting.Create(positions, new float[27 * grid.Count]);
            Assert.That(reference.SceneScale, Is.EqualTo(1.0));
            LatticeSetup(grid, 3, out int[] probes, out int[] tets);
            var result = PlacementError.Evaluate(reference, probes, tets);
            Assert.That(result.Irradiance.Mean, Is.EqualTo(0.0));
            Assert.That(result.Smape.P95, Is.EqualTo(0.0));
        }

        [TestCase(1e-6f)]
        [TestCase(1e6f)]
        public void ErrorsDoNotDependOnExposure(float exposure)
        {
            var grid = QualityFixtures.Box(6, 6, 5, 0.5);
            var positions = QualityFixtures.Jittered(QualityFixtures.Positions(grid), 0.1f, 31);
            var sh = QualityFixtures.BlobField(positions, new Vector3(0.5f, 1, 1), new Vector3(2, 2, 1.5f), 0.7f);
            int[] probes = Enumerable.Range(0, grid.Count).Where(n => n % 5 == 0).ToArray();
            int[] tets = new BowyerWatsonDelaunay().Tetrahedralize(probes.Select(p => positions[p]).ToArray());
            var plain = PlacementError.Evaluate(ReferenceLighting.Create(positions, sh), probes, tets);
            var exposed = PlacementError.Evaluate(ReferenceLighting.Create(positions, QualityFixtures.Scaled(sh, exposure)), probes, tets);
            Assert.That(plain.Irradiance.Mean, Is.GreaterThan(1e-3), "a placement with a real error");
            Assert.That(exposed.Irradiance.Mean, Is.EqualTo(plain.Irradiance.Mean).Within(1e-5 * plain.Irradiance.Mean));
            Assert.That(exposed.Irradiance.P95, Is.EqualTo(plain.Irradiance.P95).Within(1e-5 * plain.Irradiance.P95));
            Assert.That(exposed.Smape.Mean, Is.EqualTo(plain.Smape.Mean).Within(1e-5 * plain.Smape.Mean));
            Assert.That(exposed.Smape.P95, Is.EqualTo(plain.Smape.P95).Within(1e-5 * plain.Smape.P95));
        }

        [Test]
        public void AVolumeFarFromTheOriginGivesTheSameErrors()
        {
            var near = QualityFixtures.Box(7, 7, 7, 0.5);
            var far = QualityFixtures.Box(7, 7, 7, 0.5, new Double3(20000, -12000, 4096));
            LatticeSetup(near, 3, out int[] probes, out int[] tets);
            var nearPositions = QualityFixtures.Positions(near);
            var farPositions = QualityFixtures.Positions(far);
            var nearResult = PlacementError.Evaluate(ReferenceLighting.Create(nearPositions,
                QualityFixtures.BlobField(nearPositions, new Vector3(1, 1, 1), new Vector3(2, 3, 2), 1f)), probes, tets);
            var offset = farPositions[0] - nearPositions[0];
            var farResult = PlacementError.Evaluate(ReferenceLighting.Create(farPositions,
                QualityFixtures.BlobField(farPositions, new Vector3(1, 1, 1) + offset, new Vector3(2, 3, 2) + offset, 1f)), probes, tets);
            Assert.That(nearResult.Irradiance.Mean, Is.GreaterThan(1e-3));
            Assert.That(farResult.Irradiance.Mean, Is.EqualTo(nearResult.Irradiance.Mean).Within(1e-6 * nearResult.Irradiance.Mean));
            Assert.That(farResult.Smape.P95, Is.EqualTo(nearResult.Smape.P95).Within(1e-6 * nearResult.Smape.P95));
        }

        [Test]
        public void FourProbesAreEnough()
        {
            var grid = QualityFixtures.Box(4, 4, 4, 1);
            var positions = QualityFixtures.Positions(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));
            // One tetrahedron with corners (0,0,0), (3,0,0), (0,3,0), (0,0,3): exact inside, projected outside.
            int[] probes = { 0, 3, 12, 48 };
            var result = PlacementError.Evaluate(reference, probes, new[] { 0, 1, 2, 3 });
            Assert.That(result.ProbeCount, Is.EqualTo(4));
            int insideCount = Enumerable.Range(0, 64).Count(n => { var id = grid.GetId(n); return id.I + id.J + id.K <= 3; });
            Assert.That(result.OutsidePoints, Is.EqualTo(64 - insideCount));
            for (int n = 0; n < 64; n++)
            {
                var id = grid.GetId(n);
                if (id.I + id.J + id.K <= 3) Assert.That(result.PointIrradiance[n], Is.LessThan(1e-12), "inside point " + n);
                else Assert.That(result.PointIrradiance[n], Is.GreaterThan(0), "outside point " + n);
            }
        }

        [Test]
        public void TheEvaluatorTetrahedralisesTheProbesItIsGiven()
        {
            var grid = QualityFixtures.Box(6, 5, 4, 1);
            var positions = QualityFixtures.Jittered(QualityFixtures.Positions(grid), 0.2f, 41);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.BlobField(positions, new Vector3(1, 1, 1), new Vector3(4, 3, 2), 1.3f));
            int[] probes = Enumerable.Range(0, grid.Count).Where(n => n % 4 == 1).ToArray();
            var delaunay = new BowyerWatsonDelaunay();
            // Numbered by the tie rule's hash of the probes' point indices (TetrahedronNumbering), as the evaluator numbers them.
            var direct = PlacementError.Evaluate(reference, probes,
                TetrahedronNumbering.Numbered(delaunay.Tetrahedralize(probes.Select(p => positions[p]).ToArray()), probes));
            var evaluator = new PlacementEvaluator(reference, delaunay);
            Assert.That(evaluator.Evaluate(probes).PointIrradiance, Is.EqualTo(direct.PointIrradiance));
            Assert.That(evaluator.MeanError(probes), Is.EqualTo(direct.Irradiance.Mean));
        }

        [Test]
        public void BadInputsAreRejectedWithClearMessages()
        {
            var grid = QualityFixtures.Box(3, 3, 3, 1);
            var positions = QualityFixtures.Positions(grid);
            var sh = QualityFixtures.LinearField(positions, Vector3.Zero);
            var reference = ReferenceLighting.Create(positions, sh);
            int[] probes = { 0, 2, 6, 18 };
            int[] tet = { 0, 1, 2, 3 };
            Func<TestDelegate, string> message = action => Assert.Throws<PlacementErrorException>(action).Message;

            StringAssert.Contains("3 probe(s) cannot be tetrahedralised", message(() => PlacementError.Evaluate(reference, new[] { 0, 2, 6 }, tet)));
            StringAssert.Contains("1 probe(s)", message(() => PlacementError.Evaluate(reference, new[] { 0 }, tet)));
            StringAssert.Contains("probe index 27 is outside the 27 evaluation points", message(() => PlacementError.Evaluate(reference, new[] { 0, 2, 6, 27 }, tet)));
            StringAssert.Contains("probe index 6 is listed more than once", message(() => PlacementError.Evaluate(reference, new[] { 0, 6, 2, 6 }, tet)));
            StringAssert.Contains("tetrahedron 1 references probe 4, but there are only 4 probes", message(() => PlacementError.Evaluate(reference, probes, new[] { 0, 1, 2, 3, 0, 1, 2, 4 })));
            StringAssert.Contains("tetrahedron 0 uses probe 1 twice", message(() => PlacementError.Evaluate(reference, probes, new[] { 0, 1, 2, 1 })));
            StringAssert.Contains("4 probe indices each; got 5", message(() => PlacementError.Evaluate(reference, probes, new[] { 0, 1, 2, 3, 0 })));
            StringAssert.Contains("could not be tetrahedralised", message(() => PlacementError.Evaluate(reference, probes, new int[0])));
            StringAssert.Contains("listed twice", message(() => PlacementError.Evaluate(reference, probes, new[] { 0, 1, 2, 3, 3, 2, 1, 0 })));
            // Coplanar probes (z = 0 plane): their only tetrahedron is flat.
            StringAssert.Contains("lie in one plane", message(() => PlacementError.Evaluate(reference, new[] { 0, 2, 6, 8 }, tet)));
            // Three tetrahedra on one triangle: not a tetrahedralisation.
            StringAssert.Contains("belongs to 3 tetrahedra", message(() => PlacementError.Evaluate(reference, new[] { 0, 2, 6, 18, 26, 20 },
                new[] { 0, 1, 2, 3, 0, 1, 2, 4, 0, 1, 2, 5 })));

            var badSh = (float[])sh.Clone();
            badSh[27 * 5 + 9 + 3] = float.NaN;
            badSh[27 * 7] = float.PositiveInfinity;
            StringAssert.Contains("SH of point 5 is not finite (sh[g,3] = NaN; 2 points affected)", message(() => ReferenceLighting.Create(positions, badSh)));
            var badPositions = (Vector3[])positions.Clone();
            badPositions[4] = new Vector3(0, float.NaN, 0);
            StringAssert.Contains("evaluation point 4 has a non-finite position", message(() => ReferenceLighting.Create(badPositions, sh)));
            StringAssert.Contains("scene scale 0 must be", message(() => ReferenceLighting.Create(positions, sh, 0)));
            StringAssert.Contains("scene scale NaN must be", message(() => ReferenceLighting.Create(positions, sh, double.NaN)));
            StringAssert.Contains("need 27 SH coefficients per evaluation point", message(() => ReferenceLighting.Create(positions, new float[5])));
            StringAssert.Contains("coincide", message(() => ReferenceLighting.Create(new[] { Vector3.One, Vector3.One }, new float[54])));
            StringAssert.Contains("no evaluation points", message(() => ReferenceLighting.Create(new Vector3[0], new float[0])));
        }

        [Test]
        public void ALargeGridIsEvaluatedWithoutScanningEveryTetrahedron()
        {
            // 216,000 points, 8,000 probes, 41,154 tetrahedra: a linear scan would be ~9·10^9 barycentric tests.
            var grid = QualityFixtures.Box(60, 60, 60, 0.25);
            var positions = QualityFixtures.Positions(grid);
            var reference = ReferenceLighting.Create(positions, QualityFixtures.LinearField(positions, Vector3.Zero));
            int[] probes = QualityFixtures.LatticeProbes(grid, 3);
            int[] tets = QualityFixtures.KuhnTetrahedra(20, 20, 20);
            var clock = Stopwatch.StartNew();
            var result = PlacementError.Evaluate(reference, probes, tets);
            double seconds = clock.Elapsed.TotalSeconds;
            // The lattice of probes stops at id 57: the last 2 layers on each upper face are outside and extrapolated.
            Assert.That(result.OutsidePoints, Is.EqualTo(60 * 60 * 60 - 58 * 58 * 58));
            for (int n = 0; n < grid.Count; n++)
            {
                var id = grid.GetId(n);
                if (id.I <= 57 && id.J <= 57 && id.K <= 57 && result.PointIrradiance[n] > 1e-12)
                    Assert.Fail("inside point " + n + " has error " + result.PointIrradiance[n]);
            }
            Assert.That(seconds, Is.LessThan(30), InvariantFormat.Number(seconds) + " s");
            Console.WriteLine("placement error of " + grid.Count + " points, " + probes.Length + " probes: " + InvariantFormat.Number(Math.Round(seconds, 2)) + " s");
        }
    }
}
