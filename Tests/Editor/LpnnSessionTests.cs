using NUnit.Framework;
using UnityEngine;

namespace Lpnn.Probes.Editor.Tests
{
    /// <summary>A volume's session (grid, lighting, features, worker) is released with the volume, not at the next domain
    /// reload (issue 31). Compiled against the API surfaces here; runs only in a Unity editor.</summary>
    public class LpnnSessionTests
    {
        [Test]
        public void ADestroyedVolumeLosesItsSession()
        {
            var kept = new GameObject("LPNN kept").AddComponent<LpnnVolume>();
            var deleted = new GameObject("LPNN deleted").AddComponent<LpnnVolume>();
            try
            {
                var keptSession = LpnnSession.For(kept);
                LpnnSession.For(deleted);
                int before = LpnnSession.Count;
                Object.DestroyImmediate(deleted.gameObject);
                LpnnSession.ReleaseOrphans();
                Assert.That(LpnnSession.Count, Is.EqualTo(before - 1));
                Assert.That(LpnnSession.For(kept), Is.SameAs(keptSession), "a live volume keeps its session");
            }
            finally
            {
                LpnnSession.Forget(kept);
                Object.DestroyImmediate(kept.gameObject);
            }
        }
    }
}
