using System;

namespace Lpnn.Probes.Core
{
    /// <summary>Base of every error this package raises on purpose: its message names the bad value and
    /// what to do, so the editor can show it to the artist as is.</summary>
    public class LpnnException : Exception
    {
        public LpnnException(string message) : base(message) { }
        public LpnnException(string message, Exception inner) : base(message, inner) { }
    }
}
