using Lpnn.Probes.Core.Quality;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The exact signs RegularInsertion falls back to where its double evaluation is within rounding of 0: ties a
    /// double cannot see (a tie height below the lifted coordinate's last bit) are decided by the heights, and only truly
    /// coplanar or cospherical points give 0.</summary>
    [TestFixture]
    public class ExactPredicatesTests
    {
        // Five corners of the unit cube: cospherical, so their lifted points lie on one hyperplane until the heights part them.
        private static readonly double[] Corners = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1 };

        [Test]
        public void AHeightBelowTheDoublesResolutionStillDecidesTheLiftedSign()
        {
            // |q − p|² is ~1 and the height 1e-30: the double sum drops it; the exact one keeps it. Raising p above the
            // others' hyperplane takes it out of their power sphere (positive), lowering it puts it in (negative).
            Assert.That(ExactPredicates.Power(Corners, new double[] { 0, 0, 0, 0, 1e-30 }, 0, 1, 2, 3, 4), Is.EqualTo(1));
            Assert.That(ExactPredicates.Power(Corners, new double[] { 0, 0, 0, 0, -1e-30 }, 0, 1, 2, 3, 4), Is.EqualTo(-1));
            Assert.That(ExactPredicates.Power(Corners, new double[5], 0, 1, 2, 3, 4), Is.EqualTo(0), "cospherical, no heights: a true tie");
        }

        [Test]
        public void OrientationIsExactForCoplanarAndNearlyCoplanarPoints()
        {
            double[] points = { 0.1, 0.2, 0.7, 1.3, 0.2, 0.7, 0.1, 2.9, 0.7, 5.5, 3.3, 0.7, 5.5, 3.3, 0.7 + 1e-16 };
            Assert.That(ExactPredicates.Orient(points, 0, 1, 2, 3), Is.EqualTo(0), "four points in the plane z = 0.7");
            Assert.That(ExactPredicates.Orient(points, 0, 1, 2, 4), Is.EqualTo(1), "the fourth a last bit above it");
            Assert.That(ExactPredicates.Orient(points, 0, 2, 1, 4), Is.EqualTo(-1));
        }

        [Test]
        public void InAFacesPlaneThePowerCircleDecides()
        {
            // The face (0,0,0), (1,0,0), (0,1,0) in the plane z = 0; its circumcircle has centre (0.5, 0.5) and radius² 0.5.
            double[] points = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.9, 0.9, 0, 1.1, 1.1, 0 };
            Assert.That(ExactPredicates.PowerInPlane(points, new double[5], 0, 1, 2, 3), Is.EqualTo(1), "inside the circle");
            Assert.That(ExactPredicates.PowerInPlane(points, new double[5], 0, 1, 2, 4), Is.EqualTo(-1), "outside it");
        }
    }
}
