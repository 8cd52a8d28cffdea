using System.Collections.Generic;
using Lpnn.Probes.Core.Selection;
using UnityEditor;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>Scene-view drawing of a volume (DrawGizmo: UnityCsReference Editor/Mono/DrawGizmo.cs; Gizmos:
    /// Runtime/Export/Gizmos/Gizmos.bindings.cs): the boxes always, and when selected the scored evaluation points
    /// coloured by remapped score (blue low, red high) and the probes of the target group.</summary>
    internal static class LpnnGizmos
    {
        /// <summary>Gizmos are immediate mode; beyond this many points only every n-th is drawn.</summary>
        private const int MaxDrawnPoints = 20000;
        private static readonly Color BoxColor = new Color(1f, 0.75f, 0.2f, 0.9f);
        private static readonly Color ProbeColor = new Color(1f, 0.95f, 0.3f, 1f);
        private static readonly Dictionary<ObjectKey, ScoreCloud> Clouds = new Dictionary<ObjectKey, ScoreCloud>();

        private sealed class ScoreCloud
        {
            public float[] Source;
            public Vector3[] Positions;
            public Color[] Colors;
        }

        [DrawGizmo(GizmoType.Selected | GizmoType.NonSelected | GizmoType.Active)]
        private static void Draw(LpnnVolume volume, GizmoType type)
        {
            if (!volume.ShowGizmos) return;
            bool selected = (type & (GizmoType.Selected | GizmoType.Active)) != 0;
            DrawBoxes(volume, selected);
            if (!selected) return;
            DrawScores(volume);
            DrawProbes(volume.TargetGroup, volume.CellSize);
        }

        private static void DrawBoxes(LpnnVolume volume, bool selected)
        {
            var previous = Gizmos.matrix;
            Gizmos.color = selected ? BoxColor : new Color(BoxColor.r, BoxColor.g, BoxColor.b, 0.35f);
            foreach (var box in volume.Boxes)
            {
                Gizmos.matrix = volume.transform.localToWorldMatrix * Matrix4x4.TRS(box.center, box.LocalRotation, Vector3.one);
                Gizmos.DrawWireCube(Vector3.zero, box.size);
            }
            Gizmos.matrix = previous;
        }

        private static void DrawScores(LpnnVolume volume)
        {
            var record = volume.LastScores;
            if (record.IsEmpty) return;
            var cloud = CloudOf(volume, record);
            var size = Vector3.one * (float)(record.CellSize * 0.15);
            for (int p = 0; p < cloud.Positions.Length; p++)
            {
                Gizmos.color = cloud.Colors[p];
                Gizmos.DrawCube(cloud.Positions[p], size);
            }
        }

        /// <summary>Positions and colours are recomputed only when the scores array changes.</summary>
        private static ScoreCloud CloudOf(LpnnVolume volume, LpnnScoreRecord record)
        {
            var key = ObjectKey.Of(volume);
            if (Clouds.TryGetValue(key, out var cloud) && cloud.Source == record.Scores) return cloud;
            double[] remapped = ScoreRanking.Remap(record.Scores);
            int stride = Mathf.Max(1, Mathf.CeilToInt(record.Count / (float)MaxDrawnPoints));
            int drawn = (record.Count + stride - 1) / stride;
            cloud = new ScoreCloud { Source = record.Scores, Positions = new Vector3[drawn], Colors = new Color[drawn] };
            var ids = record.Ids;
            for (int d = 0, p = 0; d < drawn; d++, p += stride)
            {
                cloud.Positions[d] = new Vector3((float)(record.CellSize * ids[3 * p]), (float)(record.CellSize * ids[3 * p + 1]),
                    (float)(record.CellSize * ids[3 * p + 2]));
                var c = Color.Lerp(new Color(0.1f, 0.3f, 1f), new Color(1f, 0.15f, 0.1f), (float)remapped[p]);
                c.a = 0.35f + 0.65f * (float)remapped[p];
                cloud.Colors[d] = c;
            }
            Clouds[key] = cloud;
            return cloud;
        }

        private static void DrawProbes(LightProbeGroup group, float cellSize)
        {
            if (group == null) return;
            var local = group.probePositions;
            int stride = Mathf.Max(1, Mathf.CeilToInt(local.Length / (float)MaxDrawnPoints));
            Gizmos.color = ProbeColor;
            for (int p = 0; p < local.Length; p += stride)
                Gizmos.DrawWireSphere(group.transform.TransformPoint(local[p]), cellSize * 0.25f);
        }
    }
}
