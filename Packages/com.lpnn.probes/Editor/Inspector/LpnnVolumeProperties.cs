using UnityEditor;

namespace Lpnn.Probes.Editor
{
    /// <summary>The serialized properties of an LPNN volume the inspector edits, looked up once per inspector instead of
    /// by name on every repaint (the names are <see cref="LpnnVolume.Fields"/>, the only place they are spelled).</summary>
    internal sealed class LpnnVolumeProperties
    {
        public SerializedProperty Boxes { get; }
        public SerializedProperty CellSize { get; }
        public SerializedProperty PointLimit { get; }
        public SerializedProperty ShowGizmos { get; }
        public SerializedProperty LightingSource { get; }
        public SerializedProperty AddTemporaryColliders { get; }
        public SerializedProperty Model { get; }
        public SerializedProperty ModelCard { get; }
        public SerializedProperty Backend { get; }
        public SerializedProperty ScoringPointLimit { get; }
        public SerializedProperty TargetGroup { get; }
        public SerializedProperty Method { get; }
        public SerializedProperty Policy { get; }
        public SerializedProperty Percentile { get; }
        public SerializedProperty Budget { get; }
        public SerializedProperty Threshold { get; }
        public SerializedProperty Tolerance { get; }
        public SerializedProperty KeepBoundsCorners { get; }
        public SerializedProperty KeepPinnedProbes { get; }
        public SerializedProperty AvoidLightLeaks { get; }
        public SerializedProperty GroundTruthGroup { get; }
        public SerializedProperty DatasetFolder { get; }
        public SerializedProperty InUseRule { get; }
        public SerializedProperty InUseBandHeight { get; }
        public SerializedProperty InUseSlopeLimit { get; }
        public SerializedProperty InUseStepHeight { get; }
        public SerializedProperty InUseSeeds { get; }
        public SerializedProperty UseNavMesh { get; }

        public LpnnVolumeProperties(SerializedObject volume)
        {
            Boxes = volume.FindProperty(LpnnVolume.Fields.Boxes);
            CellSize = volume.FindProperty(LpnnVolume.Fields.CellSize);
            PointLimit = volume.FindProperty(LpnnVolume.Fields.PointLimit);
            ShowGizmos = volume.FindProperty(LpnnVolume.Fields.ShowGizmos);
            LightingSource = volume.FindProperty(LpnnVolume.Fields.LightingSource);
            AddTemporaryColliders = volume.FindProperty(LpnnVolume.Fields.AddTemporaryColliders);
            Model = volume.FindProperty(LpnnVolume.Fields.Model);
            ModelCard = volume.FindProperty(LpnnVolume.Fields.ModelCard);
            Backend = volume.FindProperty(LpnnVolume.Fields.Backend);
            ScoringPointLimit = volume.FindProperty(LpnnVolume.Fields.ScoringPointLimit);
            TargetGroup = volume.FindProperty(LpnnVolume.Fields.TargetGroup);
            Method = volume.FindProperty(LpnnVolume.Fields.Method);
            Policy = volume.FindProperty(LpnnVolume.Fields.Policy);
            Percentile = volume.FindProperty(LpnnVolume.Fields.Percentile);
            Budget = volume.FindProperty(LpnnVolume.Fields.Budget);
            Threshold = volume.FindProperty(LpnnVolume.Fields.Threshold);
            Tolerance = volume.FindProperty(LpnnVolume.Fields.Tolerance);
            KeepBoundsCorners = volume.FindProperty(LpnnVolume.Fields.KeepBoundsCorners);
            KeepPinnedProbes = volume.FindProperty(LpnnVolume.Fields.KeepPinnedProbes);
            AvoidLightLeaks = volume.FindProperty(LpnnVolume.Fields.AvoidLightLeaks);
            GroundTruthGroup = volume.FindProperty(LpnnVolume.Fields.GroundTruthGroup);
            DatasetFolder = volume.FindProperty(LpnnVolume.Fields.DatasetFolder);
            InUseRule = volume.FindProperty(LpnnVolume.Fields.InUseRule);
            InUseBandHeight = volume.FindProperty(LpnnVolume.Fields.InUseBandHeight);
            InUseSlopeLimit = volume.FindProperty(LpnnVolume.Fields.InUseSlopeLimit);
            InUseStepHeight = volume.FindProperty(LpnnVolume.Fields.InUseStepHeight);
            InUseSeeds = volume.FindProperty(LpnnVolume.Fields.InUseSeeds);
            UseNavMesh = volume.FindProperty(LpnnVolume.Fields.UseNavMesh);
        }
    }
}
