using System.Collections.Generic;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Grid;
using Lpnn.Probes.Core.InUse;
using Lpnn.Probes.Core.Scoring;
using Lpnn.Probes.Core.Selection;
using UnityEngine;

namespace Lpnn.Probes
{
    /// <summary>An LPNN volume: the boxes where light probes may go, the grid and selection settings, the model to
    /// score with and the LightProbeGroup the chosen probes are written to. All work happens in the editor
    /// (Lpnn.Probes.Editor); this component only holds settings (the last scores are editor data kept outside it), so it
    /// works in prefabs and costs nothing in a player build.</summary>
    [AddComponentMenu("Rendering/LPNN Probes Volume")]
    [DisallowMultipleComponent]
    public sealed class LpnnVolume : MonoBehaviour
    {
        /// <summary>Serialized field names, for SerializedObject.FindProperty in the editor (one place, checked by nameof).
        /// Saved scenes and prefabs hold these names: renaming a field needs [FormerlySerializedAs("oldName")], or every
        /// saved volume silently loses that setting (make test checks Tests/Editor/Data/LpnnVolume_0.1.0.prefab, a volume
        /// saved by 0.1.0, against these fields; Unity loads it in SerializationCompatibilityTests).</summary>
        public static class Fields
        {
            public const string Boxes = nameof(boxes);
            public const string CellSize = nameof(cellSize);
            public const string PointLimit = nameof(pointLimit);
            public const string LightingSource = nameof(lightingSource);
            public const string AddTemporaryColliders = nameof(addTemporaryColliders);
            public const string Model = nameof(model);
            public const string ModelCard = nameof(modelCard);
            public const string Backend = nameof(backend);
            public const string ScoringPointLimit = nameof(scoringPointLimit);
            public const string Method = nameof(placementMethod);
            public const string Policy = nameof(policy);
            public const string Percentile = nameof(percentile);
            public const string Budget = nameof(budget);
            public const string Threshold = nameof(threshold);
            public const string Tolerance = nameof(tolerance);
            public const string KeepBoundsCorners = nameof(keepBoundsCorners);
            public const string KeepPinnedProbes = nameof(keepPinnedProbes);
            public const string PinnedProbes = nameof(pinnedProbes);
            public const string AvoidLightLeaks = nameof(avoidLightLeaks);
            public const string TargetGroup = nameof(targetGroup);
            public const string GroundTruthGroup = nameof(groundTruthGroup);
            public const string DatasetFolder = nameof(datasetFolder);
            public const string ShowGizmos = nameof(showGizmos);
            public const string InUseRule = nameof(inUseRule);
            public const string InUseBandHeight = nameof(inUseBandHeight);
            public const string InUseSlopeLimit = nameof(inUseSlopeLimit);
            public const string InUseStepHeight = nameof(inUseStepHeight);
            public const string InUseSeeds = nameof(inUseSeeds);
            public const string UseNavMesh = nameof(useNavMesh);
        }

        public const float MinimumCellSize = 0.001f;
        public const float MinimumTolerance = 1e-4f;

        [Tooltip("Boxes in this object's local space; evaluation points fill their union.")]
        [SerializeField] private LpnnBox[] boxes = { new LpnnBox(Vector3.zero, new Vector3(8, 3, 8), Vector3.zero) };

        [Tooltip("Distance between evaluation points, in metres (world units).")]
        [SerializeField] private float cellSize = 0.5f;

        [Tooltip("The grid is refused above this many points (checked before anything is allocated).")]
        [SerializeField] private int pointLimit = GridBuilder.DefaultPointLimit;

        [SerializeField] private LightingSource lightingSource = LightingSource.BakeAtEvaluationPoints;

        [Tooltip("Give static renderers without colliders a temporary MeshCollider while rays are cast (removed afterwards).")]
        [SerializeField] private bool addTemporaryColliders = true;

        [Tooltip("The ONNX model (a Sentis / Inference Engine ModelAsset).")]
        [SerializeField] private Object model;

        [Tooltip("The model card (.card.json beside the .onnx) that states which features the model reads.")]
        [SerializeField] private TextAsset modelCard;

        [SerializeField] private ScoringBackendPreference backend = ScoringBackendPreference.Auto;

        [Tooltip("Scoring refuses grids above this many points (the network sees the whole cloud at once).")]
        [SerializeField] private int scoringPointLimit = ScoringPlan.DefaultMaxPoints;

        [Tooltip("How the probes are placed (Documentation~/methods.md). Insertion, refined (default) inserts probes where " +
                 "interpolating the sampled lighting is worst, then Apply removes, in batches, the ones the lighting does not need: " +
                 "the best method measured (Documentation~/benchmarks.md \"The speed/accuracy trade, every method\"), no model needed; within a few per cent of the " +
                 "reference's probe count where Insertion alone needs about 1.7x, for seconds more on rooms and minutes more on " +
                 "large volumes. Guided insertion (refined or not) takes in each of Unity's tetrahedra the badly interpolated point " +
                 "the network rates highest (after the Features and Scoring steps; measured equal once refined). Network ranks by " +
                 "the model's scores alone: milliseconds, measured worse.")]
        [SerializeField] private PlacementMethod placementMethod = PlacementMethods.Default;

        [Tooltip("How scores become probes. Tolerance (default) keeps as few spread-ranked probes as the placement error allows; " +
                 "Spread keeps Budget probes spread out and packed where the model sees lighting change; Percentile is the thesis' rule.")]
        [SerializeField] private SelectionPolicy policy = SelectionSettings.DefaultPolicy;

        [Tooltip("0.9 keeps the top 10 % of the evaluation points.")]
        [Range(0, 1)] [SerializeField] private float percentile = 0.9f;

        [Tooltip("Number of probes to keep (Spread: spread ranking; Top-K: highest scores).")]
        [SerializeField] private int budget = 256;

        [Tooltip("Keep points whose score, remapped to [0, 1], is at least this.")]
        [Range(0, 1)] [SerializeField] private float threshold = 0.5f;

        [Tooltip("Largest mean placement error allowed (default 0.05 ≈ 10 % relative irradiance error, as in lpnn place/bench/demo): " +
                 "the fewest spread-ranked probes that reproduce the sampled lighting this well.")]
        [SerializeField] private float tolerance = (float)SelectionSettings.DefaultTolerance;

        [Tooltip("Also keep the points at the 8 corners of every box, so the probes enclose the whole volume.")]
        [SerializeField] private bool keepBoundsCorners = true;

        [Tooltip("Insertion methods: Apply keeps the pinned probes (an artist's, pinned from the target group with the button " +
                 "below), counts them in the budget and the error, and puts no new probe within one cell of one " +
                 "(Documentation~/pins.md).")]
        [SerializeField] private bool keepPinnedProbes;

        // World positions of the pinned probes (Documentation~/pins.md); set by the inspector's "Pin the group's probes".
        [SerializeField] private Vector3[] pinnedProbes = new Vector3[0];

        // Added after 0.1.0: a volume saved before it loads with the default, on.
        [Tooltip("The refined methods: Apply's refinement avoids light leaking through walls (Documentation~/leaks.md): it repairs the " +
                 "tetrahedra whose probes a point cannot see (physics casts, as the Features step) and weighs leaking points 8x. " +
                 "Measured with lpnn place on 15 levels' points in use (benchmarks.md \"Light leaks\"): leaking points 8-38 % -> 0-1.2 % on 14 of them " +
                 "for a median +13 % probes, lower error near surfaces; on a whole-grid volume the price is higher (136,512 points: " +
                 "761 -> 2,854 probes, 91 % -> 14 % leaking, 2x the time). Off: fewer probes, leaks accepted.")]
        [SerializeField] private bool avoidLightLeaks = true;

        [Tooltip("The LightProbeGroup that Apply writes the chosen probes to.")]
        [SerializeField] private LightProbeGroup targetGroup;

        [Tooltip("Optional ground-truth LightProbeGroup: exported captures get labels from it (a point is positive when a probe lies in its cell).")]
        [SerializeField] private LightProbeGroup groundTruthGroup;

        [Tooltip("Folder for exported captures; empty means <project>/LpnnDatasets.")]
        [SerializeField] private string datasetFolder = "";

        [SerializeField] private bool showGizmos = true;

        // The in-use rule (Documentation~/in-use.md). Fields added after 0.1.0: a volume saved before them loads with these
        // defaults (Unity keeps a field's initial value when the saved data lacks it).
        [Tooltip("Which evaluation points placement uses and measures its error at (Documentation~/in-use.md). Reachable (default): " +
                 "the points within the band height above walkable floors that characters walk to from the seeds. Band: every point " +
                 "within the band height above a walkable floor. All: every point, for scenes whose dynamic objects fly (the error at " +
                 "the reachable points, or band points without seeds, is still reported). Band and Reachable drop the other points " +
                 "before lighting, features and placement.")]
        [SerializeField] private InUseRule inUseRule = InUseRules.Default;

        [Tooltip("Metres above a walkable floor that dynamic objects occupy (default 3.0: a 2 m character, Unity's NavMesh agentHeight " +
                 "default, jumping about 1 m, Quake III's jump: 270^2 / (2 x 800) units = 1.16 m).")]
        [SerializeField] private float inUseBandHeight = (float)InUseParameters.DefaultBandHeight;

        [Tooltip("Steepest walkable floor, in degrees from horizontal (default 45: Unity's NavMesh agentSlope default; Quake III walks " +
                 "on normals with up component >= 0.7, 45.6 degrees). In [0, 90).")]
        [SerializeField] private float inUseSlopeLimit = (float)InUseParameters.DefaultSlopeLimitDegrees;

        [Tooltip("Highest step a character climbs between neighbouring points, in metres (default 0.5: above Quake III's STEPSIZE, " +
                 "18 units = 0.457 m, and Unity's NavMesh agentClimb default, 0.4 m). Reachable only.")]
        [SerializeField] private float inUseStepHeight = (float)InUseParameters.DefaultStepHeight;

        [Tooltip("Where characters start: the scene's spawn points, items, any transform on walkable ground. The Reachable rule walks " +
                 "from the points within two cells of them; All reports the error at the points reachable from them.")]
        [SerializeField] private Transform[] inUseSeeds = new Transform[0];

        [Tooltip("When the scene has a baked NavMesh, take the walkable floors from its triangles (NavMesh.CalculateTriangulation) " +
                 "instead of physics rays against the colliders; walls still block the walk through physics rays. The NavMesh " +
                 "keeps an agent radius from walls, so points within it of a wall have no floor below them.")]
        [SerializeField] private bool useNavMesh = true;

        // Up to 0.1.0 the last scores were serialized here (field "lastScores", ~5 values per point in every scene, prefab
        // override and player build). They are editor data now (Editor: LpnnScores, issue 31); Unity skips the old field's
        // data when it loads a volume and leaves it out at the next save.

        public IReadOnlyList<LpnnBox> Boxes => boxes ?? new LpnnBox[0];
        public float CellSize => cellSize;
        public int PointLimit => pointLimit;
        public LightingSource Lighting => lightingSource;
        public bool AddTemporaryColliders => addTemporaryColliders;
        /// <summary>Kept as a plain Object so the runtime assembly never depends on Sentis; the editor checks its type.</summary>
        public Object Model => model;
        public TextAsset ModelCard => modelCard;
        public ScoringBackendPreference Backend => backend;
        public int ScoringPointLimit => scoringPointLimit;
        public LightProbeGroup TargetGroup => targetGroup;
        public LightProbeGroup GroundTruthGroup => groundTruthGroup;
        public string DatasetFolder => datasetFolder ?? "";
        public bool ShowGizmos => showGizmos;
        /// <summary>What ranks the points (<see cref="PlacementMethods.Default"/> for a new volume).</summary>
        public PlacementMethod Method => placementMethod;
        /// <summary>Whether Apply keeps <see cref="PinnedProbes"/> (Documentation~/pins.md).</summary>
        public bool KeepPinnedProbes => keepPinnedProbes;
        /// <summary>Whether Apply's refinement is leak-aware (Documentation~/leaks.md; Core.Quality.LeakWeighting over the physics rays).</summary>
        public bool AvoidLightLeaks => avoidLightLeaks;
        /// <summary>World positions of the pinned probes (a copy).</summary>
        public Vector3[] PinnedProbes => pinnedProbes == null ? new Vector3[0] : (Vector3[])pinnedProbes.Clone();

        /// <summary>Pins these world positions (the caller records Undo first), replacing the pins so far.</summary>
        public void SetPinnedProbes(Vector3[] positions) => pinnedProbes = positions == null ? new Vector3[0] : (Vector3[])positions.Clone();
        /// <summary>Whether Apply keeps the pinned probes (the inspector's Keep Pinned Probes; the caller records Undo first).</summary>
        public void SetKeepPinnedProbes(bool keep) => keepPinnedProbes = keep;
        /// <summary>Whether Apply avoids light leaks (the inspector's Avoid light leaks; the caller records Undo first).</summary>
        public void SetAvoidLightLeaks(bool avoid) => avoidLightLeaks = avoid;

        /// <summary>Which evaluation points are in use (<see cref="InUseRules.Default"/> for a new volume).</summary>
        public InUseRule InUseRule => inUseRule;
        public float InUseBandHeight => inUseBandHeight;
        public float InUseSlopeLimit => inUseSlopeLimit;
        public float InUseStepHeight => inUseStepHeight;
        /// <summary>The seed transforms as assigned (entries may be empty: <see cref="GetInUseSeedPositions"/> refuses them).</summary>
        public IReadOnlyList<Transform> InUseSeeds => inUseSeeds ?? new Transform[0];
        /// <summary>Whether floors come from the scene's baked NavMesh when there is one.</summary>
        public bool UseNavMesh => useNavMesh;

        /// <summary>The band height, slope limit and step height, checked by the core (an error names a value out of range).</summary>
        internal InUseParameters GetInUseParameters() => new InUseParameters(inUseBandHeight, inUseSlopeLimit, inUseStepHeight);

        /// <summary>The seeds' world positions; an error naming an empty entry (a deleted object) and what to do.</summary>
        public System.Numerics.Vector3[] GetInUseSeedPositions()
        {
            var seeds = InUseSeeds;
            var positions = new System.Numerics.Vector3[seeds.Count];
            for (int s = 0; s < seeds.Count; s++)
            {
                if (seeds[s] == null)
                    throw new LpnnException("entry " + s + " of the In Use Seeds of volume '" + name + "' is empty (its object was deleted?): " +
                                            "assign a transform or remove the entry");
                positions[s] = seeds[s].position.ToNumerics();
            }
            return positions;
        }

        /// <summary>The selection settings in the core's terms.</summary>
        public SelectionSettings GetSelectionSettings()
        {
            switch (policy)
            {
                case SelectionPolicy.Budget: return SelectionSettings.Budget(budget, keepBoundsCorners);
                case SelectionPolicy.Threshold: return SelectionSettings.Threshold(threshold, keepBoundsCorners);
                case SelectionPolicy.Spread: return SelectionSettings.Spread(budget, keepBoundsCorners);
                case SelectionPolicy.Tolerance: return SelectionSettings.Tolerance(tolerance, keepBoundsCorners);
                default: return SelectionSettings.Percentile(percentile, keepBoundsCorners);
            }
        }

        /// <summary>The boxes in world space, through this object's full transform (rotation and any scale).</summary>
        public List<GridBox> GetWorldBoxes()
        {
            var world = new List<GridBox>(Boxes.Count);
            var localToWorld = transform.localToWorldMatrix;
            foreach (var box in Boxes) world.Add(UnityCoreConversions.ToWorldGridBox(box, localToWorld));
            return world;
        }

        /// <summary>Assigns the target group and the model (used by the menu item, the demo and code).</summary>
        public void Configure(LightProbeGroup target, Object modelAsset, TextAsset card)
        {
            targetGroup = target;
            model = modelAsset;
            modelCard = card;
        }

        public void SetBoxes(params LpnnBox[] newBoxes) => boxes = newBoxes ?? new LpnnBox[0];

        public void SetCellSize(float size) => cellSize = Mathf.Max(MinimumCellSize, size);

        public void SetSelection(SelectionSettings settings)
        {
            policy = settings.Policy;
            keepBoundsCorners = settings.KeepBoundsCorners;
            switch (settings.Policy)
            {
                case SelectionPolicy.Budget:
                case SelectionPolicy.Spread: budget = (int)settings.Value; break;
                case SelectionPolicy.Threshold: threshold = (float)settings.Value; break;
                case SelectionPolicy.Tolerance: tolerance = (float)settings.Value; break;
                default: percentile = (float)settings.Value; break;
            }
        }

        public void SetLighting(LightingSource source) => lightingSource = source;
        public void SetMethod(PlacementMethod method) => placementMethod = method;
        public void SetBackend(ScoringBackendPreference preference) => backend = preference;
        public void SetScoringPointLimit(int limit) => scoringPointLimit = Mathf.Max(1, limit);
        public void SetGroundTruth(LightProbeGroup group) => groundTruthGroup = group;
        public void SetInUseRule(InUseRule rule) => inUseRule = rule;
        public void SetUseNavMesh(bool use) => useNavMesh = use;
        public void SetInUseSeeds(params Transform[] seeds) => inUseSeeds = seeds ?? new Transform[0];

        /// <summary>Band height and step height in metres, slope limit in degrees (checked when the grid is built).</summary>
        public void SetInUseParameters(float bandHeight, float slopeLimitDegrees, float stepHeight)
        {
            inUseBandHeight = bandHeight;
            inUseSlopeLimit = slopeLimitDegrees;
            inUseStepHeight = stepHeight;
        }

        private void OnValidate()
        {
            cellSize = Mathf.Max(MinimumCellSize, cellSize);
            pointLimit = Mathf.Max(1, pointLimit);
            scoringPointLimit = Mathf.Max(1, scoringPointLimit);
            budget = Mathf.Max(1, budget);
            // A tolerance of 0 would ask for every point; keep the field usable while typing.
            tolerance = Mathf.Max(MinimumTolerance, tolerance);
            if (boxes == null) return;
            for (int b = 0; b < boxes.Length; b++)
            {
                var s = boxes[b].size;
                boxes[b].size = new Vector3(Mathf.Abs(s.x), Mathf.Abs(s.y), Mathf.Abs(s.z));
            }
        }
    }
}
