using System;
using UnityEngine;

namespace Lpnn.Probes
{
    /// <summary>The last scores of a volume: lattice ids, one importance per evaluation point and which points are valid
    /// (not inside geometry: Documentation~/features.md "Probe validity"), serialized with the volume so the gizmos and
    /// the placement preview survive domain reloads and editor restarts.</summary>
    [Serializable]
    public sealed class LpnnScoreRecord
    {
        [SerializeField] private int[] ids = new int[0];
        [SerializeField] private float[] scores = new float[0];
        [SerializeField] private double cellSize;
        [SerializeField] private string backend = "";
        [SerializeField] private string model = "";
        [SerializeField] private bool[] valid = new bool[0];
        // Added after 0.1.0 (the in-use rule): a record saved before it has "" (unknown).
        [SerializeField] private string gridSignature = "";

        /// <summary>Lattice ids i,j,k per point, in grid order (Documentation~/grid.md).</summary>
        public int[] Ids => ids;
        public float[] Scores => scores;
        public double CellSize => cellSize;
        /// <summary>The inference backend that produced the scores (e.g. "GPUCompute", "CPU").</summary>
        public string Backend => backend;
        public string Model => model;
        public int Count => scores.Length;

        /// <summary>One flag per point, false inside geometry; null when the scores were stored before validity existed
        /// (then every point counts as valid until the Features and Scoring steps run again).</summary>
        public bool[] Valid => valid != null && valid.Length == scores.Length && valid.Length > 0 ? valid : null;

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
        public bool IsEmpty => scores.Length == 0;

        /// <summary>The editor's key of the volume settings the scored grid was built with (boxes, cell size, in-use rule and
        /// its settings), so that the scored points can be found again after a script reload; "" when unknown.</summary>
        public string GridSignature => gridSignature ?? "";

        public void SetGridSignature(string signature) => gridSignature = signature ?? "";

        /// <param name="validPoints">One flag per point (false: inside geometry), or null when unknown.</param>
        public void Set(int[] pointIds, float[] pointScores, double cell, string backendUsed, string modelName, bool[] validPoints)
        {
            if (pointIds == null || pointScores == null || pointIds.Length != 3 * pointScores.Length)
                throw new ArgumentException("need three id values (i, j, k) per score");
            if (validPoints != null && validPoints.Length != pointScores.Length)
                throw new ArgumentException("need one validity flag per score (" + pointScores.Length + "), got " + validPoints.Length);
            ids = pointIds;
            scores = pointScores;
            cellSize = cell;
            backend = backendUsed ?? "";
            model = modelName ?? "";
            valid = validPoints ?? new bool[0];
        }

        public void Clear()
        {
            Set(new int[0], new float[0], 0, "", "", null);
            gridSignature = "";
        }
    }
}
