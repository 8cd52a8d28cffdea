using System;
using System.Linq;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Selection;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The C# table of placement methods (PlacementMethods.All) against the hand-written
    /// Tests/Data/placement_methods.json, which Python's table (Training~/tests/quality/test_placement_methods.py) and
    /// Documentation~/methods.md are pinned to too: a changed name, label, need of a model or language fails here.</summary>
    [TestFixture]
    public class PlacementMethodsTests
    {
        [Test]
        public void TheCSharpRowsAreTheGoldenRowsThatNameCSharp()
        {
            var golden = TestData.ReadJson("placement_methods.json");
            var expected = golden.Get("methods").Items
                .Where(row => row.Get("languages").Items.Any(language => language.AsString == "C#"))
                .Select(row => row.Get("name").AsString + " | " + row.Get("label").AsString + " | needs model " +
                               row.Get("needs_model").AsBoolean + " | placeable " + row.Get("placeable").AsBoolean)
                .ToArray();
            var actual = PlacementMethods.All
                .Select(row => row.Name + " | " + row.Label + " | needs model " + row.NeedsScores + " | placeable True")
                .ToArray();
            Assert.That(actual, Is.EqualTo(expected));
            Assert.That(PlacementMethods.Name(PlacementMethods.Default), Is.EqualTo(golden.Get("default").AsString));
        }

        [Test]
        public void EveryEnumValueHasExactlyOneRow()
        {
            var values = Enum.GetValues(typeof(PlacementMethod)).Cast<PlacementMethod>().OrderBy(m => m).ToArray();
            Assert.That(PlacementMethods.All.Select(row => row.Method).OrderBy(m => m).ToArray(), Is.EqualTo(values));
            foreach (var method in values)
                Assert.That(PlacementMethods.Of(method).Method, Is.EqualTo(method));
        }

        [Test]
        public void WhatEachRowRunsFollowsItsName()
        {
            // The names say it: "guided" methods are guided insertion, "-refined" ones refine in batches, "network" is the
            // spread ranking; every method but the plain insertions reads the scores.
            foreach (var row in PlacementMethods.All)
            {
                Assert.That(row.GuidesInsertion, Is.EqualTo(row.Name.StartsWith("guided", StringComparison.Ordinal)), row.Name);
                Assert.That(row.RefinesInBatches, Is.EqualTo(row.Name.EndsWith("-refined", StringComparison.Ordinal)), row.Name);
                Assert.That(row.RanksByInsertion, Is.EqualTo(row.Name != "network"), row.Name);
                Assert.That(row.NeedsScores, Is.EqualTo(row.Name != "insertion" && row.Name != "insertion-refined"), row.Name);
            }
        }

        [Test]
        public void NamesParseBackInAnyCaseAndNothingElseDoes()
        {
            foreach (var row in PlacementMethods.All)
            {
                Assert.That(PlacementMethods.TryParse(row.Name, out var method), Is.True);
                Assert.That(method, Is.EqualTo(row.Method));
                Assert.That(PlacementMethods.TryParse(row.Name.ToUpperInvariant(), out method), Is.True);
                Assert.That(method, Is.EqualTo(row.Method));
            }
            Assert.That(PlacementMethods.TryParse("InsertionRefined", out _), Is.False, "the enum's name is code, not the table's");
            Assert.That(PlacementMethods.TryParse(null, out _), Is.False);
            Assert.That(PlacementMethods.Names, Is.EqualTo("insertion-refined, insertion, guided-refined, guided, network"));
        }
    }
}
