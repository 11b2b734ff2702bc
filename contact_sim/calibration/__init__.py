"""Calibration from recordings: impact times from files and audio, the bounce-sequence model
(``predict_bounces``) and its fit to recorded sequences (``fit_bounces``)."""
from contact_sim._lazy import lazy_exports

# where each public name lives, imported on first use (``contact_sim._lazy``)
_EXPORTS = {
    'audio': ('AudioOnsets', 'bounce_times_from_audio', 'detect_onsets'),
    'bounce_fit': ('fit_bounces',),
    'bounces': ('BounceSequence', 'predict_bounces'),
    'defaults': ('MICRO_BOUNCE_RATIO',),
    'glitches': ('Glitch', 'MicroBounceCut', 'PreparedSequence', 'prepare_sequence'),
    'recordings': ('ImpactTimes', 'height_from_label', 'heights_from_label', 'parse_impact_times',
                   'read_impact_times'),
    'restitution_table': ('corrected_restitution_table', 'restitution_curve'),
    'results': ('BounceFit', 'LawFit'),
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ['MICRO_BOUNCE_RATIO', 'AudioOnsets', 'BounceFit', 'BounceSequence', 'Glitch',
           'ImpactTimes', 'LawFit', 'MicroBounceCut', 'PreparedSequence',
           'bounce_times_from_audio', 'corrected_restitution_table', 'detect_onsets',
           'fit_bounces', 'height_from_label', 'heights_from_label', 'parse_impact_times',
           'predict_bounces', 'prepare_sequence', 'read_impact_times', 'restitution_curve']
