using System;
using System.Diagnostics;
using Lpnn.Probes.Core;
using Lpnn.Probes.Core.Features;
using Debug = UnityEngine.Debug;

namespace Lpnn.Probes.Editor
{
    /// <summary>Runs one inspector step: progress bar, timing, and errors turned into the step's HelpBox text plus
    /// one console entry that names the volume and says what to do. Steps publish their results only at the end, so
    /// a cancel or an exception leaves the previous state as it was.</summary>
    internal static class StepRunner
    {
        /// <summary>The work gets a progress callback and a cancellation token and returns the summary line.</summary>
        public delegate string Work(ProgressCallback progress, System.Threading.CancellationToken cancel);

        /// <returns>True when the step succeeded.</returns>
        public static bool Run(LpnnVolume volume, StepState step, Work work)
        {
            var clock = Stopwatch.StartNew();
            try
            {
                string summary;
                using (var progress = new EditorProgressScope("LPNN Probes: " + step.Name))
                    summary = work(progress.Callback, progress.Token);
                step.Succeeded(summary, clock.Elapsed.TotalSeconds);
                return true;
            }
            catch (OperationCanceledException)
            {
                step.Failed("Cancelled; the previous results are kept.", clock.Elapsed.TotalSeconds);
                return false;
            }
            catch (LpnnException e)
            {
                step.Failed(e.Message, clock.Elapsed.TotalSeconds);
                Debug.LogError("[LPNN] " + volume.name + " — " + step.Name + ": " + e.Message, volume);
                return false;
            }
            catch (Exception e)
            {
                step.Failed("Unexpected error (" + e.GetType().Name + ": " + e.Message + "). The console has the details; " +
                            "please report it with the scene if it persists.", clock.Elapsed.TotalSeconds);
                Debug.LogException(e, volume);
                return false;
            }
        }
    }
}
