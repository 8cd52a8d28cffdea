using System;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>The last scores of a volume: lattice ids, one importance per evaluation point and which points are valid (not
    /// inside geometry: Documentation~/features.md "Probe validity"). Editor data only: kept in the editor session and in
    /// the project's Library folder (<see cref="ScoreRecordFile"/>, <see cref="ScoreStore"/>), never serialized with the
    /// volume, so scenes, prefab overrides and player builds carry none of it (issue 31; until then the record was a
    /// serialized field of LpnnVolume, ~5 values per point).</summary>
    internal sealed class ScoreRecord
    {
        private int[] _ids = new int[0];
        private float[] _scores = new float[0];
        private bool[] _valid = new bool[0];
        private string _gridSignature = "";

        /// <summary>Lattice ids i,j,k per point, in grid order (Documentation~/grid.md).</summary>
        public int[] Ids => _ids;
        public float[] Scores => _scores;
        public double CellSize { get; private set; }
        /// <summary>The inference backend that produced the scores (e.g. "GPUCompute", "CPU").</summary>
        public string Backend { get; private set; } = "";
        public string Model { get; private set; } = "";
        public int Count => _scores.Length;

        /// <summary>One flag per point, false inside geometry; null when unknown (then every point counts as valid until the
        /// Features and Scoring steps run again).</summary>
        public bool[] Valid => _valid.Length == _scores.Length && _valid.Length > 0 ? _valid : null;

        public int InvalidCount
        {
            get
            {
                int count = 0;
                var flags = Valid;
                if (flags != null) foreach (bool flag in flags) if (!flag) count++;
                return count;
            }
        }

        public bool IsEmpty => _scores.Length == 0;

        /// <summary>The editor's key of the volume settings the scored grid was built with (boxes, cell size, in-use rule and
        /// its settings), so that the scored points can be found again after a script reload; "" when unknown.</summary>
        public string GridSignature => _gridSignature;

        public void SetGridSignature(string signature) => _gridSignature = signature ?? "";

        /// <param name="validPoints">One flag per point (false: inside geometry), or null when unknown.</param>
        public void Set(int[] pointIds, float[] pointScores, double cell, string backendUsed, string modelName, bool[] validPoints)
        {
            if (pointIds == null || pointScores == null || pointIds.Length != 3 * (long)pointScores.Length)
                throw new ArgumentException("need three id values (i, j, k) per score");
            if (validPoints != null && validPoints.Length != pointScores.Length)
                throw new ArgumentException("need one validity flag per score (" + pointScores.Length + "), got " + validPoints.Length);
            _ids = pointIds;
            _scores = pointScores;
            CellSize = cell;
            Backend = backendUsed ?? "";
            Model = modelName ?? "";
            _valid = validPoints ?? new bool[0];
        }

        public void Clear()
        {
            Set(new int[0], new float[0], 0, "", "", null);
            _gridSignature = "";
        }
    }
}
