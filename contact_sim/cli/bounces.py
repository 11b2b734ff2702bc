"""`contact-sim bounces`: calibrate a contact from recorded bounce sequences (impact times or
audio): the laws fitted by ``calibration.fit_bounces``, ranked, and the best one's report."""
import argparse
import math
import sys

import numpy as np

# the parser's defaults and choices, from modules without the engine (contact_sim._lazy): the
# fit, the audio detector and the drag are imported in the functions that run them
from contact_sim.calibration import MICRO_BOUNCE_RATIO
from contact_sim.cli import plotting
from contact_sim.cli.contact import lacks_hertz_stiffness, mass_of, material
from contact_sim.cli.options import LAW_NAMES, contact_command, law_list
from contact_sim.flight import AIR_DENSITY, SPHERE_DRAG_COEFFICIENT
from contact_sim.impact import LOSSES
from contact_sim.model import build_contact
from contact_sim.validation import require_positive

LINEAR_DERIVED = """\
with
               materials and no --stiffness the linear law is kept: its k is derived (its
               undamped contact lasts as long as the Hertz one at the median impact speed)
               when a Hertz law is fitted beside it; alone, it needs --stiffness."""

UNTRUSTED_FIT = 3     # the exit status of a report whose best fit is not to be trusted

NOTES = """

data: CSV files of impact times (s), one column per sequence (several runs side by side are
fine; --column picks some; --group-by splits a long table by its trial columns, --where keeps
the rows of one ball), or phyphox
"Acoustic Stopwatch" exports read as they are (.xlsx/.xls workbooks, the CSV
of the All sheet, any separator and decimal comma, or the zip of the CSV export), or WAV
recordings of the bounces (the clicks are found by contact_sim.calibration.audio).  Columns
that number the events (event_index, 0 1 2 ...) are not times; an interval column beside a time
column restores a last event kept only as an interval.  A release height in a column header or
file name (h=0.8, 80cm, Lancio1,10cm = 0.10 m) is used: a file name's one height for every run
in the file, or one height per run in order; --height overrides them, once per sequence.

what is fitted: for every law, lambda (k fixed: --stiffness or Hertz), per sequence its start
time and first impact speed, and with --fit-drag the drag coefficient, by robust least squares
on the click times (soft-L1 scaled to three times the timing noise).  Air drag
1/2 rho C_d pi R1^2 v^2 acts in flight when --radius is given (C_d 0.47 unless
--drag-coefficient; 0 turns it off).
The constant-restitution law is the linear law (its k is derived unless --stiffness is given).

micro-bounces: the final clicks, where each impact lasts a sizeable share of its bounce, are
beyond the bounce model; they are left out from the first impact whose undamped contact time
(of the softest law's k) exceeds --micro-bounce-ratio times the flight before it, or from the
first flight shorter than --min-flight.  A k guessed too soft cuts too early: raise the ratio
(inf turns it off) or give --min-flight instead; the glitches list says where and why.

--holdout F: the glitches are named on the whole of each sequence; the laws are fitted on all
the clicks (the fit reported, plotted and saved) and again on all but the last share F of each
sequence (the training fit, printed beside it), which predicts the held-out clicks (their rms
per sequence and overall is printed): what a fit is worth beyond the clicks it saw.

fits say how they ended: each law's line ends with `fit: converged`, `ILL-DETERMINED` (an
interval wider than a factor 100, or no more clicks than parameters), `AT-BOUND` (C_d at a
bound of [0.001, 10]) or `FAILED` (no convergence in 5000 evaluations), and why.  Fewer
observations (clicks and heights) than fitted parameters are refused.  `model adequacy`
compares the best law's e residuals with the recording's own scatter of e about a smooth
curve (F test; with --holdout, on the held-out flights): when the law leaves more than that
scatter (p < 0.001) it does not describe the recording, and the reason names a trend it
cannot follow (e.g. a restitution that rises with speed); the speed-dependence verdict is then
undecided.  Workbooks: every sheet; what is found and not read is listed (`# read:`).
exit status 3: the report is printed, but the best fit is not `converged` or does not
describe the recording (a warning on stderr says why).

example (python examples/bounce_recording.py writes golf_80cm_50cm.csv):
  contact-sim bounces golf_80cm_50cm.csv --sphere steel --plate steel --radius 0.0214 \\
      --mass 0.0459 --stiffness 2e8 --fit-drag --save-params golf.yaml
"""


def _float_list(text):
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f'invalid value {text!r}: allowed a number') from None


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
        sub, 'bounces', damping=False,
        help='calibrate lambda (and drag) from recorded bounce times or audio',
        description='Fit each law to recorded bounce sequences by least squares on the impact\n'
                    'times (cs.fit_bounces), with drag and contact duration in the\n'
                    'model, detector glitches named, and the laws ranked.',
        notes=NOTES, linear=LINEAR_DERIVED)
    p.add_argument('data', nargs='+', help='CSV / phyphox export (.csv, .zip) or .wav files')
    p.add_argument('--law', action='append', choices=LAW_NAMES,
                   help='force law, repeatable (default: all four)')
    p.add_argument('--column', action='append', metavar='COL',
                   help='read only this column of the CSV files: its header or its number from '
                        '1 (repeatable; default every time column)')
    p.add_argument('--group-by', metavar='COL[,COL...]',
                   help='a long table of trials: one sequence per combination of the values of '
                        'these columns (headers or numbers from 1, separated by commas: '
                        'ball,height_cm,trial), the times from --column or the first time '
                        'column; a height in a value (80cm, or 80 under height_cm) is that '
                        'sequence\'s')
    p.add_argument('--where', action='append', metavar='COL=VALUE',
                   help='read only the rows whose column COL (header or number from 1) holds '
                        'VALUE, e.g. --where ball=golf (repeatable: every condition holds)')
    p.add_argument('--height', action='append', type=_float_list, metavar='H',
                   help='release height in m of each sequence, in order (repeatable)')
    p.add_argument('--height-error', type=float, default=0.01, metavar='DH',
                   help='uncertainty of a measured release height in m (default 0.01)')
    p.add_argument('--gravity', type=float, default=9.81, help='m/s^2 (default 9.81)')
    p.add_argument('--air-density', type=float, default=AIR_DENSITY, metavar='RHO',
                   help=f'kg/m^3 (default {AIR_DENSITY})')
    p.add_argument('--drag-coefficient', type=float, default=None, metavar='CD',
                   help=f'C_d of the sphere (default {SPHERE_DRAG_COEFFICIENT} with --radius; '
                        '0 = no drag)')
    p.add_argument('--fit-drag', action='store_true',
                   help='fit C_d too (needs --radius); its interval is printed')
    p.add_argument('--timing-resolution', type=float, default=1.0 / 48000.0, metavar='S',
                   help='clock resolution in s (default 1/48000, a phone)')
    p.add_argument('--loss', choices=LOSSES, default='soft_l1',
                   help='least-squares loss (default soft_l1: robust against outliers)')
    p.add_argument('--confidence', type=float, default=0.95,
                   help='confidence level of the intervals, 0 < C < 1 (default 0.95)')
    p.add_argument('--micro-bounce-ratio', type=float, default=MICRO_BOUNCE_RATIO, metavar='R',
                   help='leave out the final clicks from the first impact whose contact time '
                        '(undamped, of the softest law) exceeds R times the flight before it '
                        f'(default {MICRO_BOUNCE_RATIO:g}; inf: never)')
    p.add_argument('--min-flight', type=float, default=0.0, metavar='S',
                   help='and from the first flight shorter than S seconds (default 0: none)')
    p.add_argument('--holdout', type=float, metavar='F',
                   help='fit the laws on the first clicks of each sequence and predict its '
                        'last share F of clicks, 0 < F < 1; the prediction rms is printed')
    p.add_argument('--plot', metavar='OUT.png',
                   help='also draw e vs speed with each law and the timing residuals')
    p.add_argument('--save-params', metavar='FILE.yaml',
                   help="write the best law as a node parameter file (contact_sim_node "
                        "--ros-args --params-file FILE.yaml)")
    p.set_defaults(run=run)
    return p


def _sequences(args):
    from contact_sim.calibration import (ImpactTimes, bounce_times_from_audio,   # the engine:
                                         height_from_label, read_impact_times)   # after parsing
    sequences, notes = [], []
    where = _where(args.where)
    for path in args.data:
        if str(path).lower().endswith('.wav'):
            onsets = bounce_times_from_audio(path)
            print(f'# audio {path}: {onsets.summary()}')
            sequences.append(ImpactTimes(onsets.times, height_from_label(
                str(path).rsplit('/', 1)[-1]), f'{path} (audio)'))
        else:
            sequences.extend(read_impact_times(path, columns=args.column,
                                               group_by=args.group_by, where=where,
                                               notes=notes, named=not args.height))
    for note in notes:
        print(f'# read: {note}')
    if args.height:
        if len(args.height) != len(sequences):
            raise ValueError(f'height is given {len(args.height)} time(s) for '
                             f'{len(sequences)} sequence(s): allowed one --height per sequence')
        sequences = [ImpactTimes(s.times, require_positive('height', h), s.name)
                     for s, h in zip(sequences, args.height)]
    return sequences


def _where(conditions):
    """--where COL=VALUE conditions as a mapping column -> value (None without any)."""
    if not conditions:
        return None
    where = {}
    for text in conditions:
        column, sep, value = text.partition('=')
        if not sep or not column.strip() or not value.strip():
            raise ValueError(f'--where = {text!r} is not COL=VALUE: allowed a column (header '
                             'or number from 1), =, and the value its rows hold, e.g. '
                             '--where ball=golf')
        if column.strip() in where:
            raise ValueError(f'--where names the column {column.strip()!r} twice: allowed one '
                             'value per column')
        where[column.strip()] = value.strip()
    return where


def _stiffness(args, laws):
    """k per law (``ContactLaw`` keys): --stiffness, or the Hertz k by the core's one rule
    (Hertz laws only)."""
    if args.stiffness is not None:
        k = require_positive('stiffness', args.stiffness)
        return {law: k for law in laws}, 'given'
    sphere, plate = material(args, 'sphere'), material(args, 'plate')
    ks = {}
    for law in laws:
        if lacks_hertz_stiffness(args, law, sphere, plate):
            continue     # it is left out of the ranking
        ks[law] = build_contact(law, sphere=sphere, plate=plate, radius=args.radius,
                                plate_radius=args.plate_radius, damping=0.0).stiffness
    return ks, 'Hertz'


def _drag(args):
    from contact_sim.flight import AirDrag   # the engine: after the arguments are parsed
    if args.radius is None:
        if args.fit_drag or (args.drag_coefficient or 0.0) > 0.0:
            raise ValueError('radius is missing: drag needs the sphere radius --radius R1 (m)')
        return None
    cd = SPHERE_DRAG_COEFFICIENT if args.drag_coefficient is None else args.drag_coefficient
    drag = AirDrag(args.air_density, cd, args.radius)
    if not drag.active and not args.fit_drag:
        return None
    return drag


def run(args):
    """Fit the laws to the recordings, print the report (and draw it with --plot, save the
    node parameters with --save-params); returns the exit status: 0, or ``UNTRUSTED_FIT`` when
    the best fit failed or no law describes the recording (the report is printed all the
    same)."""
    from contact_sim.calibration import corrected_restitution_table, fit_bounces   # the engine
    laws = law_list(args, LAW_NAMES)
    mass = mass_of(args)
    drag = _drag(args)
    ks, k_source = _stiffness(args, laws)
    sequences = _sequences(args)
    fit = fit_bounces(ks, mass, sequences, laws=laws, gravity=args.gravity, drag=drag,
                      fit_drag=args.fit_drag, timing_resolution=args.timing_resolution,
                      height_error=args.height_error, loss=args.loss, confidence=args.confidence,
                      holdout=args.holdout, micro_bounce_ratio=args.micro_bounce_ratio,
                      min_flight=args.min_flight)
    table = corrected_restitution_table(fit)
    print_report(fit, sequences, args, k_source, table)
    if args.plot:
        _plot(args, fit, table)
    if args.save_params:
        write_params(args.save_params, fit, args)
        print(f'# node parameters written to {args.save_params}')
    if not fit.trustworthy:
        why = fit_status(fit.best) if not fit.best.success else fit.adequacy.reason
        print(f'contact-sim: warning: the best fit ({fit.best.law.name}) is not to be trusted: '
              f'{why}', file=sys.stderr)
        return UNTRUSTED_FIT
    return 0


def print_report(fit, sequences, args, k_source, table):
    """The fit's report: the data and drag, the glitches, the laws ranked, the corrected
    restitution ``table`` and the predicted against the measured click times."""
    from contact_sim.calibration import restitution_curve
    level = f'{100 * fit.confidence:g}%'
    clicks = sum(s.times.size for s in sequences)
    print(f'# bounce fit: {len(sequences)} sequence(s), {clicks} clicks; m = {fit.mass:.6g} kg, '
          f'g = {fit.gravity:g} m/s^2, k {k_source}')
    if fit.drag is None:
        print('# drag: none (vacuum flights)')
    else:
        what = 'fitted, start' if fit.fit_drag else 'fixed'
        print(f'# drag: rho = {fit.drag.air_density:g} kg/m^3, R1 = {fit.drag.radius:g} m, '
              f'C_d {what} {fit.drag.drag_coefficient:g}')
    for j, s in enumerate(sequences):
        h = f'released from {s.height:g} m' if s.height is not None else 'release height unknown'
        print(f'# sequence {j + 1}: {s.name}, {s.times.size} clicks, {h}')
    named = [g for g in fit.glitches if g.kind != 'outlier']
    print(f'# glitches: {len(named) or "none"}')
    for g in named:
        print(f'#   {g.describe()}')
    if not any(s.height is not None for s in sequences):
        print('#   (without a release height a late start cannot be told from a lower release)')
    print(f'# laws ranked by weighted rms timing residual (equal parameter counts: '
          f'{fit.best.parameters} each); AIC = N ln(SSE/N) + 2P')
    for f in fit.fits:
        print(f'{f.law.name}: lambda = {f.damping:.6e} {_interval(f.damping_interval, level)}, '
              f'k = {f.stiffness:.6e}, rms = {f.rms * 1e3:.4f} ms, AIC = {f.aic:.2f}')
        if fit.fit_drag:
            print(f'  drag coefficient C_d = {f.drag_coefficient:.4f} '
                  f'{_interval(f.drag_interval, level, ".4g")}')
        print(f'  fit: {fit_status(f)}')
    if math.isfinite(fit.delta_aic):
        verdict = ('supported' if fit.speed_dependent else 'NOT supported') \
            if fit.adequacy.adequate else 'undecided (the best law does not describe the ' \
            'recording)'
        print(f'speed-dependent restitution: {verdict} (constant-restitution AIC minus the best '
              f'speed-dependent law\'s: {fit.delta_aic:.2f}; needs > 10)')
    word = 'INADEQUATE' if not fit.adequacy.adequate else 'not judged' \
        if fit.adequacy.judged_on == 'none' else 'adequate'
    print(f'model adequacy ({fit.adequacy.judged_on}): {word}: {fit.adequacy.reason}')
    best = fit.best
    print(f'timing noise (robust estimate): {best.noise * 1e3:.4f} ms')
    down = fit.downweighted()
    print(f'down-weighted clicks (robust weight < 0.5): {len(down) or "none"}')
    for j, t, r, w in down:
        print(f'  sequence {j + 1}: t = {t:.6f} s, residual {r * 1e3:+.3f} ms, weight {w:.2f}')
    print(f'# drag- and duration-corrected restitution ({best.law.name}); e from each flight')
    print(f'# {"seq":>3} {"speed (m/s)":>12} {"e":>9} {"sigma_e":>9} {"e model":>9}')
    for j, v, e, se in table:
        model = float(restitution_curve(best, fit.mass, v))
        print(f'  {j + 1:3d} {v:12.5f} {e:9.5f} {se:9.5f} {model:9.5f}')
    print(f'# predicted vs measured click times ({best.law.name})')
    print(f'# {"seq":>3} {"bounce":>6} {"measured (s)":>13} {"predicted (s)":>13} '
          f'{"residual (ms)":>13} {"weight":>6}')
    for j, (s, r, w) in enumerate(zip(fit.sequences, best.residuals, best.weights)):
        for n, t, ri, wi in zip(s.index, s.times, r, w):
            print(f'  {j + 1:3d} {n + 1:6d} {t:13.6f} {t + ri:13.6f} {ri * 1e3:13.4f} {wi:6.2f}')
    print(f'rms predicted - measured: {best.rms * 1e3:.4f} ms')
    if fit.holdout is not None:
        print_holdout(fit)


def fit_status(law_fit):
    """``converged (solver message)``, ``ILL-DETERMINED: why`` or ``FAILED: why``."""
    if law_fit.success:
        return f'converged ({law_fit.message})'
    return f'{law_fit.status.upper()}: {law_fit.message}'


def print_holdout(fit):
    """The hold-out check: each law fitted on the earlier clicks beside its fit on all of them,
    and the held-out clicks of each sequence predicted by the former."""
    level = f'{100 * fit.confidence:g}%'
    print('# hold-out: each law fitted on the earlier clicks of each sequence (training) '
          'predicts the last ones; the fit on all the clicks (above) is the one reported, '
          'plotted and saved')
    for h in fit.holdout:
        full = next(f for f in fit.fits if f.law is h.law)
        train = h.fit
        drag = (f', C_d {train.drag_coefficient:.4f} (all: {full.drag_coefficient:.4f})'
                if fit.fit_drag else '')
        print(f'{h.law.name}: training lambda = {train.damping:.6e} '
              f'{_interval(train.damping_interval, level)} (all clicks: {full.damping:.6e}){drag}'
              f', training rms {train.rms * 1e3:.4f} ms, fit: {fit_status(train)}')
    print(f'# {"seq":>3} {"held out":>8} ' + ' '.join(f'{h.law.name + " (ms)":>22}'
                                                       for h in fit.holdout))
    for j, seq in enumerate(fit.holdout[0].held):
        print(f'  {j + 1:3d} {seq.times.size:8d} ' + ' '.join(f'{h.rms[j] * 1e3:22.4f}'
                                                              for h in fit.holdout))
    for h in fit.holdout:
        print(f'hold-out rms ({h.law.name}): {h.overall * 1e3:.4f} ms over '
              f'{sum(s.times.size for s in h.held)} clicks')


def _interval(interval, level, spec='.6e'):
    """``[low, high] (level)``, or ``(no interval)`` when the fit did not determine one."""
    low, high = interval
    if not (math.isfinite(low) and math.isfinite(high)):
        return '(no interval: see the fit message)'
    return f'[{low:{spec}}, {high:{spec}}] ({level})'


def _yaml_number(value):
    """A plain YAML float (``21450572.48``, never ``np.float64(...)``), as the node reads it."""
    return repr(float(value))


def write_params(path, fit, args):
    """A ROS 2 parameter file for contact_sim_node (names from its PARAMETERS): the best law's
    fit on all the clicks, and the ball calibrated (mass, radius, materials), so that the node
    logs that ball: a library material by name, else ``custom`` with the moduli given, or
    with the ball's mean density only (k and lambda are set: the moduli are not used)."""
    best = fit.best
    heights = [s.height for s in fit.sequences if s.height is not None]
    clicks = sum(s.times.size for s in fit.sequences)
    ball = f'm = {fit.mass:g} kg' + (f', R1 = {args.radius:g} m' if args.radius else '')
    lines = ['# contact calibrated by `contact-sim bounces` from ' + ', '.join(args.data),
             f'# the fit on all {clicks} clicks of {len(fit.sequences)} sequence(s)'
             + (' (not the hold-out\'s training fit)' if fit.holdout else ''),
             f'# {best.law.name}: rms timing residual {best.rms * 1e3:.4f} ms; lambda '
             f'{_interval(best.damping_interval, f"{fit.confidence * 100:g}%")}; fit '
             f'{fit_status(best)}',
             f'# model adequacy ({fit.adequacy.judged_on}): '
             f'{"adequate" if fit.adequacy.adequate else "INADEQUATE"}',
             f'# ball: {ball}', 'contact_sim:', '  ros__parameters:',
             f'    contact_law: {best.law.name}']
    values = {'stiffness': best.stiffness, 'damping': best.damping, 'sphere_mass': fit.mass,
              'gravity': fit.gravity}
    if args.radius is not None:
        values['sphere_radius'] = args.radius
    if heights:
        values['initial_height'] = heights[0]
    if fit.drag is not None:
        values['air_density'] = fit.drag.air_density
    values['drag_coefficient'] = best.drag_coefficient if fit.drag is not None else 0.0
    lines += [f'    {name}: {_yaml_number(value)}' for name, value in values.items()]
    for body in ('sphere', 'plate'):
        chosen = material(args, body)
        if chosen is not None and chosen.name == getattr(args, body):
            lines.append(f'    {body}_material: {chosen.name}')
            continue
        lines.append(f'    {body}_material: custom')
        if chosen is not None:          # the moduli given (--sphere-modulus ...)
            lines += [f'    {body}_{key}: {_yaml_number(getattr(chosen, key))}'
                      for key in ('youngs_modulus', 'poisson_ratio', 'density')]
        elif body == 'sphere' and args.radius is not None:   # the ball's mean density
            density = fit.mass / (4.0 / 3.0 * math.pi * args.radius ** 3)
            lines.append(f'    sphere_density: {_yaml_number(density)}')
    try:
        with open(path, 'w', encoding='utf-8') as f:
            f.write('\n'.join(lines) + '\n')
    except OSError as error:
        raise ValueError(f'--save-params = {path!r} cannot be written: {error.strerror}') \
            from None


def _plot(args, fit, table):
    """The figure of ``plotting.bounce_figure``: the corrected e(v) with every law's curve (its
    status in the legend), the best law's timing residuals per run and, with --holdout, its
    prediction of the held-out clicks."""
    from contact_sim.calibration import restitution_curve
    columns = [np.array(c) for c in zip(*table)] if table else [np.zeros(0)] * 4
    curves = {}
    if table:
        v = columns[1]
        dense = np.geomspace(v.min() * 0.8, v.max() * 1.2, 200)
        for f in fit.fits:
            marks = [] if f.success else [f.status.upper()]
            if f is fit.best and not fit.adequacy.adequate:
                marks.append('INADEQUATE')
            label = f'{f.law.name}: rms {f.rms * 1e3:.3g} ms' + \
                (f' [{", ".join(marks)}]' if marks else '')
            curves[label] = (dense, restitution_curve(f, fit.mass, dense))
    runs = [((s.name or f'sequence {j + 1}').replace('\\', '/').rsplit('/', 1)[-1],
             s.times - s.times[0]) for j, s in enumerate(fit.sequences)]
    held, held_label = None, ''
    if fit.holdout:
        h = next(h for h in fit.holdout if h.law is fit.best.law)
        held = [(s.times - fit.sequences[j].times[0], r)
                for j, (s, r) in enumerate(zip(h.held, h.residuals))]
        held_label = (f'held out, predicted by the training fit: rms {h.overall * 1e3:.3g} ms '
                      f'({fit.adequacy.judged_on}: '
                      f'{"adequate" if fit.adequacy.adequate else "INADEQUATE"})')
    names = [str(d).replace('\\', '/').rsplit('/', 1)[-1] for d in args.data]
    title = (f'Bounce calibration of {names[0]}' + (f' and {len(names) - 1} more file(s)'
                                                     if len(names) > 1 else '')
             + f': best {fit.best.law.name}, '
             + ('converged' if fit.best.success else fit.best.status.upper())
             + ('' if fit.adequacy.adequate else ', INADEQUATE'))
    fig = plotting.bounce_figure(args.plot, columns, curves, runs, fit.best.residuals,
                                 fit.best.law.name, title, scatter=fit.adequacy.scatter,
                                 held=held, held_label=held_label)
    print(f'# plot written to {args.plot}')
    return fig
