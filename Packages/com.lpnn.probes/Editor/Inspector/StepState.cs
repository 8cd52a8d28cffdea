namespace Lpnn.Probes.Editor
{
    /// <summary>What the inspector shows for one step: done or not, a one-line summary, the last duration and the
    /// last error (with what to do).</summary>
    internal sealed class StepState
    {
        public string Name { get; }
        public bool Done { get; private set; }
        public string Summary { get; private set; } = "";
        public string Error { get; private set; } = "";
        public string Warning { get; private set; } = "";
        /// <summary>Seconds the last run took; negative when it never ran.</summary>
        public double Seconds { get; private set; } = -1;

        public StepState(string name) { Name = name; }

        public void Succeeded(string summary, double seconds, string warning = "")
        {
            Done = true;
            Summary = summary ?? "";
            Warning = warning ?? "";
            Error = "";
            Seconds = seconds;
        }

        /// <summary>A caveat about a successful result (shown beside it until the step runs again).</summary>
        public void Warn(string warning) => Warning = warning ?? "";

        /// <summary>A failed or cancelled run: the previous result (if any) stays valid, only the message changes.</summary>
        public void Failed(string error, double seconds)
        {
            Error = error ?? "";
            Seconds = seconds;
        }

        /// <summary>Inputs changed: the result no longer matches the volume.</summary>
        public void Reset()
        {
            Done = false;
            Summary = "";
            Warning = "";
            Error = "";
        }
    }
}
