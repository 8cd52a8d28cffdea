using System;
using System.Globalization;
using System.IO;
using System.Linq;
using System.Text;
using System.Threading;
using Lpnn.Probes.Core.Captures;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.IO;
using Lpnn.Probes.Core.Json;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Tests.Support;
using NUnit.Framework;

namespace Lpnn.Probes.Core.Tests
{
    [TestFixture]
    public class CaptureTests
    {
        private string _folder;
        private CultureInfo _culture;

        [SetUp]
        public void CreateFolderUnderAGermanLocale()
        {
            _folder = Path.Combine(Path.GetTempPath(), "lpnn-capture-tests-" + Guid.NewGuid().ToString("N"));
            Directory.CreateDirectory(_folder);
            _culture = Thread.CurrentThread.CurrentCulture;
            Thread.CurrentThread.CurrentCulture = new CultureInfo("de-DE");
        }

        [TearDown]
        public void Cleanup()
        {
            Thread.CurrentThread.CurrentCulture = _culture;
            if (Directory.Exists(_folder)) Directory.Delete(_folder, true);
        }

        internal static Capture SmallCapture(bool labels = true)
        {
            var grid = GridBuilder.Build(new[] { GridBox.AxisAligned(new Double3(0, 0, 0), new Double3(1, 1, 0.5)) }, 0.5);
            var sh = new float[grid.Count * 27];
            var features = new float[grid.Count * FeatureSchema.LpnnV1.Count];
            for (int n = 0; n < sh.Length; n++) sh[n] = 0.001f * n - 0.2f;
            for (int n = 0; n < features.Length; n++) features[n] = (float)Math.Sin(n) * 0.0226f;
            var set = new FeatureSet(FeatureSchema.LpnnV1, grid.Count, features, 0.125);
            var source = JsonValue.NewObject();
            source.Set("scene", JsonValue.From("unit-test room"));
            source.Set("exposure", JsonValue.From(2.338238e-05));
            var capture = Capture.FromGrid(grid, sh, set, source);
            if (!labels) return capture;
            var labelValues = new byte[grid.Count];
            labelValues[3] = labelValues[7] = 1;
            return capture.WithLabels(labelValues, "probes:unit test");
        }

        [Test]
        public void SaveAndReadRoundTripEveryField()
        {
            var capture = SmallCapture();
            string path = Path.Combine(_folder, "room.lpnncap");
            CaptureFile.Save(path, capture);
            var read = CaptureFile.Read(path);
            Assert.That(read.PointCount, Is.EqualTo(capture.PointCount));
            Assert.That(read.Ids, Is.EqualTo(capture.Ids));
            Assert.That(read.Positions, Is.EqualTo(capture.Positions));
            Assert.That(read.Sh, Is.EqualTo(capture.Sh));
            Assert.That(read.Features, Is.EqualTo(capture.Features));
            Assert.That(read.Labels, Is.EqualTo(capture.Labels));
            Assert.That(read.LabelSource, Is.EqualTo("probes:unit test"));
            Assert.That(read.CellSize, Is.EqualTo(0.5));
            Assert.That(read.LightingScale, Is.EqualTo(0.125));
            Assert.That(read.Schema, Is.EqualTo("lpnn.features.v1"));
            Assert.That(read.Source.Get("exposure").AsNumber, Is.EqualTo(2.338238e-05));
            Assert.That(read.ToGrid().Count, Is.EqualTo(capture.PointCount));
        }

        [Test]
        public void HeaderIsCultureInvariantAndOutputIsDeterministic()
        {
            byte[] first = CaptureFile.Encode(SmallCapture());
            byte[] second = CaptureFile.Encode(SmallCapture());
            Assert.That(first, Is.EqualTo(second));
            string header = Encoding.UTF8.GetString(first, 16, BitConverter.ToInt32(first, 12));
            StringAssert.Contains("\"cell_size\": 0.5", header);
            StringAssert.Contains("\"exposure\": 2.338238E-05", header);
            StringAssert.DoesNotContain("0,5", header);
            Assert.That((16 + header.Length) % 8, Is.EqualTo(0), "sections start 8-byte aligned");
        }

        [Test]
        public void AppendNeverAltersAnExistingCapture()
        {
            var capture = SmallCapture();
            string first = CaptureFile.Append(_folder, capture, "room");
            byte[] before = File.ReadAllBytes(first);
            string second = CaptureFile.Append(_folder, SmallCapture(false), "room");
            string third = CaptureFile.Append(_folder, capture, "room");
            Assert.That(Path.GetFileName(first), Is.EqualTo("room.lpnncap"));
            Assert.That(Path.GetFileName(second), Is.EqualTo("room-2.lpnncap"));
            Assert.That(Path.GetFileName(third), Is.EqualTo("room-3.lpnncap"));
            Assert.That(File.ReadAllBytes(first), Is.EqualTo(before));
            Assert.That(Directory.GetFiles(_folder).Length, Is.EqualTo(3), "no temporary files are left behind");
            Assert.That(CaptureFile.Read(second).Labels, Is.Null);
        }

        [Test]
        public void UnknownHeaderKeysAndExtraSectionsSurviveARewrite()
        {
            string path = Path.Combine(_folder, "a.lpnncap");
            var capture = SmallCapture();
            var extraHeader = JsonValue.NewObject();
            extraHeader.Set("future_key", JsonValue.From("kept"));
            var scores = new byte[capture.PointCount * 4];
            var withExtras = new Capture(capture.Ids, capture.Positions, capture.Sh, capture.Features, capture.Schema, capture.FeatureNames,
                capture.CellSize, capture.Units, capture.LightingScale, capture.Labels, capture.LabelSource, capture.Source,
                new[] { new CaptureSection("scores", "float32", new[] { capture.PointCount }, scores) }, extraHeader);
            CaptureFile.Save(path, withExtras);
            var read = CaptureFile.Read(path);
            Assert.That(read.ExtraHeader.Get("future_key").AsString, Is.EqualTo("kept"));
            Assert.That(read.ExtraSections[0].Name, Is.EqualTo("scores"));
            CaptureFile.Save(path, read);
            Assert.That(File.ReadAllBytes(path), Is.EqualTo(CaptureFile.Encode(withExtras)));
        }

        private string Write(byte[] bytes)
        {
            string path = Path.Combine(_folder, "bad.lpnncap");
            File.WriteAllBytes(path, bytes);
            return path;
        }

        [Test]
        public void TruncatedWrongMagicWrongVersionAndCorruptFilesAreNamed()
        {
            byte[] good = CaptureFile.Encode(SmallCapture());
            var truncated = new byte[good.Length - 40];
            Array.Copy(good, truncated, truncated.Length);
            StringAssert.Contains("(truncated?)", Assert.Throws<CaptureException>(() => CaptureFile.Read(Write(truncated))).Message);

            var zip = (byte[])good.Clone();
            zip[0] = (byte)'P';
            zip[1] = (byte)'K';
            StringAssert.Contains("byte 0: not a capture (magic is 'PKNNCAP\\x00'", Assert.Throws<CaptureException>(() => CaptureFile.Read(Write(zip))).Message);

            var version = (byte[])good.Clone();
            version[8] = 9;
            StringAssert.Contains("format version 9 is not supported", Assert.Throws<CaptureException>(() => CaptureFile.Read(Write(version))).Message);

            var corrupt = (byte[])good.Clone();
            corrupt[corrupt.Length - 100] ^= 0x40;
            StringAssert.Contains("the file is corrupt", Assert.Throws<CaptureException>(() => CaptureFile.Read(Write(corrupt))).Message);

            StringAssert.Contains("cannot read", Assert.Throws<CaptureException>(() => CaptureFile.Read(Path.Combine(_folder, "missing.lpnncap"))).Message);
        }

        [Test]
        public void BadValuesAreReportedWithRecordIdAndField()
        {
            var capture = SmallCapture();
            capture.Sh[27 * 5 + 9 + 2] = float.NaN;
            capture.Features[19 * 2 + 4] = float.PositiveInfinity;
            capture.Labels[1] = 7;
            // Encoding refuses invalid content, so build the bytes from a valid capture and patch them.
            var clean = SmallCapture();
            byte[] bytes = CaptureFile.Encode(clean);
            int headerLength = BitConverter.ToInt32(bytes, 12);
            int shOffset = 16 + headerLength + Pad(clean.PointCount * 12) + Pad(clean.PointCount * 12);
            Array.Copy(BitConverter.GetBytes(float.NaN), 0, bytes, shOffset + 4 * (27 * 5 + 9 + 2), 4);
            FixCrc(bytes);
            string path = Write(bytes);
            var error = Assert.Throws<CaptureException>(() => CaptureFile.Read(path));
            StringAssert.Contains("record 5 (id 2,1,0): field 'sh[g,2]': NaN is not finite", error.Message);
            Assert.Throws<CaptureException>(() => CaptureFile.Encode(capture));
        }

        [Test]
        public void ValidateReportsEveryProblem()
        {
            var clean = SmallCapture();
            byte[] bytes = CaptureFile.Encode(clean);
            int headerLength = BitConverter.ToInt32(bytes, 12);
            int featureOffset = 16 + headerLength + Pad(clean.PointCount * 12) * 2 + Pad(clean.PointCount * 108);
            Array.Copy(BitConverter.GetBytes(float.NaN), 0, bytes, featureOffset + 4 * (19 * 2 + 4), 4);
            Array.Copy(BitConverter.GetBytes(float.NegativeInfinity), 0, bytes, featureOffset + 4 * (19 * 6 + 0), 4);
            FixCrc(bytes);
            var problems = CaptureFile.Validate(Write(bytes));
            Assert.That(problems.Count, Is.EqualTo(2));
            StringAssert.Contains("record 2 (id 2,0,0): field 'features[light_variance]'", problems[0]);
            StringAssert.Contains("record 6 (id 0,2,0): field 'features[log_luminance]'", problems[1]);
            Assert.That(CaptureFile.Validate(Write(CaptureFile.Encode(clean))), Is.Empty);
        }

        [Test]
        public void HeaderProblemsNameTheField()
        {
            byte[] bytes = CaptureFile.Encode(SmallCapture());
            int headerLength = BitConverter.ToInt32(bytes, 12);
            string header = Encoding.UTF8.GetString(bytes, 16, headerLength);
            string patched = header.Replace("\"cell_size\": 0.5", "\"cell_size\": -0.5");
            Array.Copy(Encoding.UTF8.GetBytes(patched), 0, bytes, 16, patched.Length);
            FixCrc(bytes);
            StringAssert.Contains("header: field 'cell_size': -0.5 is not a finite number > 0",
                Assert.Throws<CaptureException>(() => CaptureFile.Read(Write(bytes))).Message);
            string broken = header.Replace("\"units\": \"m\",", "\"units\": \"m\" ");
            Array.Copy(Encoding.UTF8.GetBytes(broken), 0, bytes, 16, broken.Length);
            StringAssert.Contains("header line 1, column", Assert.Throws<CaptureException>(() => CaptureFile.Read(Write(bytes))).Message);
        }

        private static int Pad(int length) => length + (8 - length % 8) % 8;

        private static void FixCrc(byte[] bytes)
        {
            uint crc = Crc32.Update(0, bytes, 0, bytes.Length - 16);
            Array.Copy(BitConverter.GetBytes(crc), 0, bytes, bytes.Length - 16, 4);
        }

        [Test]
        public void Crc32MatchesZlib()
        {
            // zlib.crc32(b"123456789") = 0xCBF43926, the standard check value
            Assert.That(Crc32.Update(0, Encoding.ASCII.GetBytes("123456789"), 0, 9), Is.EqualTo(0xCBF43926u));
            byte[] data = Encoding.ASCII.GetBytes("123456789");
            Assert.That(Crc32.Update(Crc32.Update(0, data, 0, 4), data, 4, 5), Is.EqualTo(0xCBF43926u), "running CRC");
        }

        [Test]
        public void AFailedWriteKeepsTheOldFileAndLeavesNoTemporaryFile()
        {
            string path = Path.Combine(_folder, "keep.txt");
            File.WriteAllText(path, "old");
            Assert.Throws<InvalidOperationException>(() => AtomicFile.Write(path, stream =>
            {
                stream.WriteByte(1);
                throw new InvalidOperationException("disk full");
            }));
            Assert.That(File.ReadAllText(path), Is.EqualTo("old"));
            Assert.That(Directory.GetFiles(_folder).Length, Is.EqualTo(1));
            AtomicFile.WriteAllBytes(path, Encoding.ASCII.GetBytes("new"));
            Assert.That(File.ReadAllText(path), Is.EqualTo("new"));
            Assert.That(AtomicFile.WriteNew(path, s => s.WriteByte(1)), Is.False);
            Assert.That(File.ReadAllText(path), Is.EqualTo("new"));
        }

        [Test]
        public void LegacyThesisFilesImportWithCommaDecimalsAndExponents()
        {
            var text = new StringBuilder("30\n");
            for (int point = 0; point < 3; point++)
            {
                for (int line = 0; line < 6; line++) text.Append("0,0226 1.5 2,338238E-05 -3\n");
                text.Append("0,1 0,2\n0,3 0,4 0,5 0,6\n\n\n");
            }
            string features = Path.Combine(_folder, "features.txt");
            string labels = Path.Combine(_folder, "comparisons.txt");
            File.WriteAllText(features, text.ToString());
            File.WriteAllText(labels, "True\nfalse\n\nTRUE\n");
            var capture = LegacyThesisFiles.ToCapture(features, labels, "corridor");
            Assert.That(capture.PointCount, Is.EqualTo(3));
            Assert.That(capture.Schema, Is.EqualTo("lpnn.thesis30"));
            Assert.That(capture.Features[0], Is.EqualTo(0.0226f));
            Assert.That(capture.Features[2], Is.EqualTo(2.338238e-05f));
            Assert.That(capture.Features[29], Is.EqualTo(0.6f));
            Assert.That(capture.Labels, Is.EqualTo(new byte[] { 1, 0, 1 }));
            CaptureFile.Save(Path.Combine(_folder, "legacy.lpnncap"), capture);
            Assert.That(CaptureFile.Read(Path.Combine(_folder, "legacy.lpnncap")).Source.Get("legacy").AsBoolean, Is.True);
        }

        [Test]
        public void LegacyCountMismatchesAreExplained()
        {
            string features = Path.Combine(_folder, "features.txt");
            File.WriteAllText(features, "4 values\n1 2 3 4\n\n1 2 3\n\n");
            var error = Assert.Throws<CaptureException>(() => LegacyThesisFiles.ReadFeatures(features));
            StringAssert.Contains("features.txt:4: point 1 has 3 values, expected 4", error.Message);

            File.WriteAllText(features, "2\n1 2\n\n3,5 4\n");
            Assert.That(LegacyThesisFiles.ReadFeatures(features)[1][0], Is.EqualTo(3.5f));
            string labels = Path.Combine(_folder, "comparisons.txt");
            File.WriteAllText(labels, "True\n");
            string block = string.Join(" ", Enumerable.Repeat("0,5", 30));
            File.WriteAllText(features, "30\n" + block + "\n\n" + block + "\n");
            StringAssert.Contains("1 labels for 2 feature blocks", Assert.Throws<CaptureException>(() => LegacyThesisFiles.ToCapture(features, labels, null)).Message);
            File.WriteAllText(labels, "True\nmaybe\n");
            StringAssert.Contains("comparisons.txt:2: expected True or False, found 'maybe'", Assert.Throws<CaptureException>(() => LegacyThesisFiles.ReadLabels(labels)).Message);
            File.WriteAllText(features, "2\n1 x\n");
            StringAssert.Contains("features.txt:2: 'x' is not a finite number", Assert.Throws<CaptureException>(() => LegacyThesisFiles.ReadFeatures(features)).Message);
        }
    }
}
