"""Calibration from recordings: impact times from files and audio, the bounce-sequence model
(``predict_bounces``) and its fit to recorded sequences (``fit_bounces``)."""
from contact_sim.calibration.audio import AudioOnsets, bounce_times_from_audio, detect_onsets
from contact_sim.calibration.bounce_fit import fit_bounces
from contact_sim.calibration.bounces import BounceSequence, predict_bounces
from contact_sim.calibration.glitches import (MICRO_BOUNCE_RATIO, Glitch, MicroBounceCut,
                                              PreparedSequence, prepare_sequence)
from contact_sim.calibration.recordings import (ImpactTimes, height_from_label, heights_from_label,
                                                parse_impact_times, read_impact_times)
from contact_sim.calibration.restitution_table import (corrected_restitution_table,
                                                       restitution_curve)
from contact_sim.calibration.results import BounceFit, LawFit

__all__ = ['MICRO_BOUNCE_RATIO', 'AudioOnsets', 'BounceFit', 'BounceSequence', 'Glitch',
           'ImpactTimes', 'LawFit', 'MicroBounceCut', 'PreparedSequence',
           'bounce_times_from_audio', 'corrected_restitution_table', 'detect_onsets',
           'fit_bounces', 'height_from_label', 'heights_from_label', 'parse_impact_times',
           'predict_bounces', 'prepare_sequence', 'read_impact_times', 'restitution_curve']
