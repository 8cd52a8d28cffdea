using System;
using UnityEngine;

namespace Lpnn.Probes
{
    /// <summary>The last scores of a volume: lattice ids and one importance per evaluation point, serialized with the
    /// volume so the gizmos and the placement preview survive domain reloads and editor restarts.</summary>
    [Serializable]
    public sealed class LpnnScoreRecord
    {
        [SerializeField] private int[] ids = new int[0];
        [SerializeField] private float[] scores = new float[0];
        [SerializeField] private double cellSize;
        [SerializeField] private string backend = "";
        [SerializeField] private string model = "";

        /// <summary>Lattice ids i,j,k per point, in grid order (Documentation~/grid.md).</summary>
        public int[] Ids => ids;
        public float[] Scores => scores;
        public double CellSize => cellSize;
        /// <summary>The inference backend that produced the scores (e.g. "GPUCompute", "CPU").</summary>
        public string Backend => backend;
        public string Model => model;
        public int Count => scores.Length;
        public bool IsEmpty => scores.Length == 0;

        public void Set(int[] pointIds, float[] pointScores, double cell, string backendUsed, string modelName)
        {
            if (pointIds == null || pointScores == null || pointIds.Length != 3 * pointScores.Length)
                throw new ArgumentException("need three id values (i, j, k) per score");
            ids = pointIds;
            scores = pointScores;
            cellSize = cell;
            backend = backendUsed ?? "";
            model = modelName ?? "";
        }

        public void Clear() => Set(new int[0], new float[0], 0, "", "");
    }
}
