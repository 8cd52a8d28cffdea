using System.Collections.Generic;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.Numerics;
using Lpnn.Probes.Core.Placement;
using UnityEditor;

namespace Lpnn.Probes.Editor
{
    /// <summary>The Volume section's readout: how many evaluation points the boxes and cell size give and what they cost,
    /// counted without building the grid and only when the boxes, cell size or point limit change.</summary>
    internal sealed class PointCountEstimate
    {
        /// <summary>Points above which the inspector asks before running a heavy step.</summary>
        public const long LargeGrid = HeavyOperationPolicy.LargeGrid;

        private string _signature;

        public string Text { get; private set; } = "";
        public MessageType Type { get; private set; } = MessageType.Info;
        /// <summary>The points the current settings give (0 when they are invalid).</summary>
        public long Points { get; private set; }

        public void Update(LpnnVolume volume, LpnnSession session)
        {
            string signature;
            List<GridBox> boxes;
            try
            {
                boxes = volume.GetWorldBoxes();
                // The session's signature too: the note on a stale grid follows a rebuild and an in-use setting change.
                signature = GridSignature.Of(volume) + "|" + volume.PointLimit + "|" + session.GridSignature;
            }
            catch (LpnnException e)
            {
                Show(e.Message, MessageType.Error);
                return;
            }
            if (signature == _signature) return;
            _signature = signature;
            try
            {
                Points = GridBuilder.CountPoints(boxes, volume.CellSize, volume.PointLimit);
                string text = InvariantFormat.Count(Points) + " evaluation points; about " + CostOf(Points) + " through the pipeline.";
                var type = MessageType.Info;
                if (Points > volume.PointLimit)
                {
                    text += " Over the point limit of " + InvariantFormat.Count(volume.PointLimit) + ": use a larger cell size or smaller boxes.";
                    type = MessageType.Error;
                }
                else if (Points > LargeGrid)
                {
                    text += " That is a large grid: lighting and features will take a while (you will be asked before they run).";
                    type = MessageType.Warning;
                }
                if (session.Grid != null && session.GridSignature != GridSignature.Of(volume))
                    text += "\nThe volume or its in-use settings changed since the grid was built: build it again.";
                Show(text, type);
            }
            catch (LpnnException e)
            {
                Points = 0;
                Show(e.Message, MessageType.Error);
            }
        }

        /// <summary>The memory a grid of this many points takes through the pipeline.</summary>
        public static string CostOf(long points) => StepSummaries.Megabytes(EvaluationGrid.EstimateBytes(points, FeatureExtractor.Schema.Count));

        private void Show(string text, MessageType type)
        {
            Text = text;
            Type = type;
        }
    }
}
