#!/usr/bin/env python3
"""Make a bounce recording to try `contact-sim bounces` on: a phyphox "Acoustic Stopwatch" CSV
export (All sheet; semicolon separator, decimal comma) and a WAV file, from the package's own
drop engine.  Not a measurement: a golf-like ball (m = 45.9 g, R1 = 21.4 mm, k = 2e8 N/m^1.5,
Azad-Featherstone law with e = 0.8 at 3 m/s, drag coefficient 0.25) dropped twice, from 0.8 m
and 0.5 m; 50 us timing jitter, times in multiples of 1/48000 s; the detector doubled one click
of the first run and missed a bounce of the second.

    python examples/bounce_recording.py [OUT_DIR]   # writes golf_80cm_50cm.csv, golf_80cm.wav
"""
import pathlib
import sys

import numpy as np

import contact_sim as cs
from contact_sim.calibration import audio
from contact_sim.flight import AirDrag

MASS, RADIUS, STIFFNESS, DRAG_COEFFICIENT = 0.0459, 0.0214, 2e8, 0.25


def touches(height, count=12):
    lam = cs.damping_for_restitution(cs.AZAD_FEATHERSTONE, STIFFNESS, MASS, 0.8, 3.0)
    contact = cs.Contact(cs.AZAD_FEATHERSTONE, STIFFNESS, lam)
    result = cs.simulate_drop(contact, MASS, height, duration=12.0 * (2 * height / 9.81) ** 0.5,
                              drag=AirDrag(1.204, DRAG_COEFFICIENT, RADIUS))
    impacts = result.impacts[:count]
    return np.array([i.time for i in impacts]), np.array([i.impact_speed for i in impacts]), lam


def main(out_dir='.'):
    out = pathlib.Path(out_dir)
    rng = np.random.default_rng(2024)
    runs = []
    for height, start in ((0.8, 1.7), (0.5, 0.9)):
        t, _, lam = touches(height)
        runs.append(np.round((t + start + rng.normal(0.0, 50e-6, t.size)) * 48000) / 48000)
    runs[0] = np.sort(np.append(runs[0], runs[0][3] + 0.0117))     # an echo fired twice
    runs[1] = np.delete(runs[1], 7)                                 # a quiet bounce missed
    rows = ['"Event time (s) 80cm";"Interval (s)";"Event time (s) 50cm";"Interval (s)"']
    for i in range(max(r.size for r in runs)):
        cells = []
        for r in runs:
            if i < r.size:
                interval = f'{r[i + 1] - r[i]:.6f}' if i + 1 < r.size else ''
                cells += [f'{r[i]:.6f}', interval]
            else:
                cells += ['', '']
        rows.append(';'.join(c.replace('.', ',') for c in cells))
    csv_path = out / 'golf_80cm_50cm.csv'
    csv_path.write_text('\n'.join(rows) + '\n')
    # the first drop as sound: clicks as loud as the impact speed, room noise, an echo
    t, speeds, _ = touches(0.8)
    samples = audio.synthesize_recording(t + 0.5, 0.6 * speeds / speeds[0], rate=48000)
    wav_path = out / 'golf_80cm.wav'
    audio.write_wav(wav_path, samples, 48000, 16)
    print(f'wrote {csv_path} and {wav_path} (true lambda = {lam:.6e} N s/m^1.5, '
          f'C_d = {DRAG_COEFFICIENT})')
    return csv_path, wav_path, lam


if __name__ == '__main__':
    main(*sys.argv[1:2])
