using System;
using System.Threading;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Grid;

namespace Lpnn.Probes.Editor
{
    /// <summary>One way of obtaining the baked lighting (27 SH floats, Documentation~/sh.md) at every evaluation point.</summary>
    public interface IEvaluationLighting : IDisposable
    {
        /// <summary>What was done, for the inspector, the console and the capture's provenance.</summary>
        string Description { get; }

        float[] Sample(EvaluationGrid grid, ProgressCallback progress, CancellationToken cancel);
    }
}
