using System;
using System.Collections.Generic;
using System.Linq;
using Lpnn.Probes.Core.Scoring;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    /// <summary>The scores kept outside the volume (issue 31; Core.Scoring.ScoreStore, ScoreRecordFile): the record, its
    /// file, which volumes get one, the prune and the 0.1.0 overrides the inspector removes.</summary>
    [TestFixture]
    public class ScoreStoreTests
    {
        private const string Key = "GlobalObjectId_V1-2-0123456789abcdef0123456789abcdef-1234567890-0";

        private static ScoreRecord Record(bool withValidity)
        {
            var record = new ScoreRecord();
            record.Set(new[] { 0, 0, 0, 1, 0, 0, 2, 5, -3 }, new[] { 0.25f, 1f, float.Epsilon }, 0.5, "CPU", "lpnn_pointnet_v1",
                withValidity ? new[] { true, false, true } : null);
            record.SetGridSignature("boxes=…;cell=0.5;rule=Reachable");
            return record;
        }

        [TestCase(true)]
        [TestCase(false)]
        public void ARecordReadsBackExactly(bool withValidity)
        {
            var record = Record(withValidity);
            var back = ScoreRecordFile.Decode(ScoreRecordFile.Encode(record, Key), Key, "test");
            Assert.That(back.Ids, Is.EqualTo(record.Ids));
            Assert.That(back.Scores, Is.EqualTo(record.Scores));
            Assert.That(back.CellSize, Is.EqualTo(0.5));
            Assert.That(back.Backend, Is.EqualTo("CPU"));
            Assert.That(back.Model, Is.EqualTo("lpnn_pointnet_v1"));
            Assert.That(back.GridSignature, Is.EqualTo(record.GridSignature), "UTF-8 strings");
            Assert.That(back.Valid, Is.EqualTo(record.Valid));
            Assert.That(back.InvalidCount, Is.EqualTo(withValidity ? 1 : 0));
        }

        [Test]
        public void AnEmptyRecordReadsBackEmpty()
        {
            var back = ScoreRecordFile.Decode(ScoreRecordFile.Encode(new ScoreRecord(), Key), Key, "test");
            Assert.That(back.IsEmpty, Is.True);
            Assert.That(back.Valid, Is.Null);
        }

        [Test]
        public void AFileOfAnotherVolumeReadsAsNoScores()
        {
            byte[] bytes = ScoreRecordFile.Encode(Record(true), Key);
            Assert.That(ScoreRecordFile.Decode(bytes, Key.Replace("1234567890", "42"), "test"), Is.Null);
        }

        [Test]
        public void DamageIsRefusedWithWhatIsWrong()
        {
            byte[] bytes = ScoreRecordFile.Encode(Record(true), Key);
            var flipped = (byte[])bytes.Clone();
            flipped[bytes.Length / 2] ^= 0x10;
            StringAssert.Contains("checksum", Assert.Throws<ScoringException>(() => ScoreRecordFile.Decode(flipped, Key, "x")).Message);
            StringAssert.Contains("LPNNSCR1", Assert.Throws<ScoringException>(() => ScoreRecordFile.Decode(new byte[40], Key, "x")).Message);
            // a truncated file whose checksum happens to be recomputed still cannot claim more points than it holds
            var truncated = bytes.Take(bytes.Length - 20).ToArray();
            uint crc = Lpnn.Probes.Core.Captures.Crc32.Update(0, truncated, 0, truncated.Length);
            var resealed = truncated.Concat(BitConverter.GetBytes(crc)).ToArray();
            Assert.Throws<ScoringException>(() => ScoreRecordFile.Decode(resealed, Key, "x"));
        }

        [Test]
        public void ARecordNeedsThreeIdsAndAtMostOneFlagPerScore()
        {
            var record = new ScoreRecord();
            Assert.Throws<ArgumentException>(() => record.Set(new int[2], new float[1], 1, "", "", null));
            Assert.Throws<ArgumentException>(() => record.Set(new int[3], new float[1], 1, "", "", new bool[2]));
            record.Set(new int[3], new float[1], 1, null, null, null);
            Assert.That(record.Backend, Is.EqualTo(""));
            record.SetGridSignature("s");
            record.Clear();
            Assert.That(record.IsEmpty && record.GridSignature == "", Is.True);
        }

        [TestCase("GlobalObjectId_V1-2-0123456789abcdef0123456789abcdef-1234567890-0", true, TestName = "a scene object of a saved scene")]
        [TestCase("GlobalObjectId_V1-2-0123456789abcdef0123456789abcdef-1234567890-987654321", true, TestName = "a prefab instance's object")]
        [TestCase("GlobalObjectId_V1-1-0123456789abcdef0123456789abcdef-1234567890-0", true, TestName = "an object of a prefab asset")]
        [TestCase("GlobalObjectId_V1-0-00000000000000000000000000000000-0-0", false, TestName = "the null id (unsaved or preview scene)")]
        [TestCase("GlobalObjectId_V1-2-00000000000000000000000000000000-1234-0", false, TestName = "no asset GUID")]
        [TestCase("GlobalObjectId_V1-2-0123456789abcdef0123456789abcdef-0-0", false, TestName = "no object id")]
        [TestCase("GlobalObjectId_V2-2-0123456789abcdef0123456789abcdef-1-0", false, TestName = "an unknown format")]
        [TestCase("", false, TestName = "empty")]
        public void OnlyStableIdsGetAFile(string id, bool persistent)
        {
            Assert.That(ScoreStore.IsPersistentKey(id), Is.EqualTo(persistent));
        }

        [Test]
        public void FileNamesAreShortHashesOfTheKey()
        {
            string name = ScoreStore.FileName(Key);
            StringAssert.EndsWith(ScoreStore.Extension, name);
            Assert.That(name.Length, Is.EqualTo(32 + ScoreStore.Extension.Length));
            Assert.That(ScoreStore.FileName(Key), Is.EqualTo(name), "stable");
            Assert.That(ScoreStore.FileName(Key + "1"), Is.Not.EqualTo(name));
        }

        [Test]
        public void ThePruneKeepsTheMostRecentWithinTheLimits()
        {
            var t = new DateTime(2026, 1, 1, 0, 0, 0, DateTimeKind.Utc);
            var files = new List<ScoreStore.StoredFile>();
            for (int f = 0; f < 5; f++) files.Add(new ScoreStore.StoredFile { Name = "f" + f, WrittenUtc = t.AddMinutes(f), Bytes = 100 });
            Assert.That(ScoreStore.ToPrune(files, 3, 1000), Is.EquivalentTo(new[] { "f0", "f1" }), "at most 3 files");
            Assert.That(ScoreStore.ToPrune(files, 10, 250), Is.EquivalentTo(new[] { "f0", "f1", "f2" }), "at most 250 bytes");
            files.Add(new ScoreStore.StoredFile { Name = "huge", WrittenUtc = t.AddHours(1), Bytes = 5000 });
            var pruned = ScoreStore.ToPrune(files, 10, 1000);
            Assert.That(pruned, Has.No.Member("huge"), "the newest is always kept");
            Assert.That(pruned.Count, Is.EqualTo(5));
            Assert.That(ScoreStore.ToPrune(new ScoreStore.StoredFile[0]), Is.Empty);
        }

        [TestCase("lastScores", true)]
        [TestCase("lastScores.scores.Array.data[17]", true)]
        [TestCase("lastScores.ids.Array.size", true)]
        [TestCase("lastScoresOther", false)]
        [TestCase("cellSize", false)]
        [TestCase(null, false)]
        public void TheRetiredFieldsOverridesAreRecognised(string path, bool legacy)
        {
            Assert.That(ScoreStore.IsLegacyScorePath(path), Is.EqualTo(legacy));
        }
    }
}
