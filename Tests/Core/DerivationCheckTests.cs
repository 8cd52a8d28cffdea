using System;
using Lpnn.Probes.Core.Quality;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The one rule by which derived tetrahedra are trusted (DerivationCheck; its callers, insertion rounds and
    /// refinement trials, are tested with real tetrahedralisers in InsertionTetrahedraTests and StarRefillTests):
    /// compare until one agrees, re-synchronise on a disagreement, stop deriving after MaxResyncs disagreements before
    /// any agreement.</summary>
    [TestFixture]
    public class DerivationCheckTests
    {
        [Test]
        public void AFirstAgreementEndsTheComparisons()
        {
            var check = new DerivationCheck();
            Assert.That(check.Derives && check.Compares, Is.True, "a fresh check derives and compares");
            Assert.That(check.Record(true), Is.True);
            Assert.That(check.Agrees, Is.True);
            Assert.That(check.Compares, Is.False, "nothing is compared once one agreed");
            Assert.That(check.Derives, Is.True);
            Assert.That(check.Resyncs, Is.EqualTo(0));
        }

        [Test]
        public void DisagreementsBeforeAnyAgreementStopDerivingAtTheLimit()
        {
            var check = new DerivationCheck();
            for (int k = 1; k < DerivationCheck.MaxResyncs; k++)
            {
                Assert.That(check.Record(false), Is.False);
                Assert.That(check.Resyncs, Is.EqualTo(k));
                Assert.That(check.Derives, Is.True, "a disagreement re-synchronises and derives again");
                Assert.That(check.Compares, Is.True, "and the next derivation is compared again");
            }
            check.Record(false);
            Assert.That(check.Derives, Is.False, "MaxResyncs disagreements before any agreement: stop deriving");
            Assert.That(check.Agrees, Is.False);
        }

        [Test]
        public void AnAgreementAfterDisagreementsKeepsDeriving()
        {
            var check = new DerivationCheck();
            for (int k = 1; k < DerivationCheck.MaxResyncs; k++) check.Record(false);
            Assert.That(check.Record(true), Is.True);
            Assert.That(check.Derives, Is.True);
            Assert.That(check.Compares, Is.False);
            Assert.That(check.Resyncs, Is.EqualTo(DerivationCheck.MaxResyncs - 1));
        }

        [Test]
        public void ComparingAfterAnAgreementIsRefused()
        {
            var check = new DerivationCheck();
            check.Record(true);
            Assert.Throws<InvalidOperationException>(() => check.Record(false));
        }
    }
}
