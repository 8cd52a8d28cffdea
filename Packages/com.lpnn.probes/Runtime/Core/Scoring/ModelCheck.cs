using System.Collections.Generic;

namespace Lpnn.Probes.Core.Scoring
{
    /// <summary>One failed check of a model or its card: what is wrong and what to do, with its severity. The checks return
    /// every problem they find (an artist fixes them in one pass instead of one per scoring attempt); the inspector shows
    /// them all.</summary>
    public sealed class ModelCheck
    {
        public CheckSeverity Severity { get; }
        public string Message { get; }

        public ModelCheck(CheckSeverity severity, string message)
        {
            Severity = severity;
            Message = message ?? "";
        }

        public static ModelCheck Error(string message) => new ModelCheck(CheckSeverity.Error, message);
        public static ModelCheck Warning(string message) => new ModelCheck(CheckSeverity.Warning, message);

        public override string ToString() => Severity + ": " + Message;

        public static bool AnyError(IEnumerable<ModelCheck> checks)
        {
            foreach (var check in checks)
                if (check.Severity == CheckSeverity.Error) return true;
            return false;
        }

        /// <summary>Throws one <see cref="ModelCardException"/> carrying every error (one per line) when there is any.</summary>
        public static void ThrowIfAnyError(IReadOnlyList<ModelCheck> checks)
        {
            var errors = new List<string>();
            foreach (var check in checks)
                if (check.Severity == CheckSeverity.Error) errors.Add(check.Message);
            if (errors.Count > 0) throw new ModelCardException(string.Join("\n", errors));
        }
    }
}
