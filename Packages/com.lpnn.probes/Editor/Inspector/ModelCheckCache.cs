using System.Collections.Generic;
using Lpnn.Probes.Core.Features;
using Lpnn.Probes.Core.Scoring;
using UnityEngine;

namespace Lpnn.Probes.Editor
{
    /// <summary>The Scoring section's list of model and card problems (<see cref="LpnnScoring.Checks"/>), re-checked only
    /// when the Model or Card field changes (the card is parsed, not the model loaded).</summary>
    internal sealed class ModelCheckCache
    {
        private TextAsset _card;
        private Object _model;
        private bool _checked;
        private IReadOnlyList<ModelCheck> _checks = new ModelCheck[0];

        public IReadOnlyList<ModelCheck> For(LpnnVolume volume)
        {
            if (_checked && volume.ModelCard == _card && volume.Model == _model) return _checks;
            _card = volume.ModelCard;
            _model = volume.Model;
            _checked = true;
            _checks = LpnnScoring.Checks(volume, FeatureExtractor.Schema, out ModelCard _);
            return _checks;
        }
    }
}
