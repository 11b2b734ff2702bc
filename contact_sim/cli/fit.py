"""`contact-sim fit`: the damping lambda fitted to measured (speed, restitution) points, per law,
with k fixed from the materials or --stiffness (the paper's Fig. 5)."""
import contextlib
import csv
import io
import math
import sys

import numpy as np

from contact_sim.cli import plotting
from contact_sim.cli.contact import build_setup, contact_lines, damping_unit, describe_contact
from contact_sim.cli.options import LAW_NAMES, contact_command, law_list, plot_option
from contact_sim.impact import LOSSES   # (a module without the engine: contact_sim._lazy)
from contact_sim.validation import InputError, number_from_text, require_range


def add_parser(sub):
    """Register the subcommand on the subparsers ``sub``."""
    p = contact_command(
        sub, 'fit', damping=False,
        help='fit the damping lambda to measured (speed, restitution) points',
        description='Least-squares fit of lambda to measured restitution (cs.fit_damping for\n'
                    'one law, cs.compare_laws for several), with k fixed from the materials\n'
                    'or --stiffness, as in the paper\'s Fig. 5.',
        notes='\n\ndata file: rows "speed,restitution" (m/s, 0 < e; e >= 1 is kept and flagged)\n'
              'and optionally a third column, the uncertainty of e (used as weights 1/u^2);\n'
              'further columns are ignored; an optional header row; text after # is a\n'
              'comment; - reads stdin.\n\nexample:\n'
              '  contact-sim fit data.csv --sphere steel --plate cast_iron --radius 0.0127\n')
    p.add_argument('data', help='CSV file of speed,restitution rows, or - for stdin')
    p.add_argument('--law', action='append', choices=LAW_NAMES,
                   help='force law, repeatable (default: all four, ranked by rms residual)')
    p.add_argument('--confidence', type=float, default=0.95,
                   help='confidence level of the interval on lambda, 0 < C <= 0.999999 (default 0.95)')
    p.add_argument('--loss', choices=LOSSES, default='linear',
                   help='least-squares loss (default linear; soft_l1 etc. down-weight outliers)')
    plot_option(p, 'the data and the fitted curves on a log speed axis')
    p.set_defaults(run=run)



MAX_LINE = 10_000   # characters of a data row (csv's own field limit is 131072)


def _is_number(text):
    try:
        float(text)
    except ValueError:
        return False
    return True


def _cell(name, text):
    """A positive number from a data file's cell (``InputError`` naming ``name``)."""
    return require_range(name, number_from_text(name, text), 0.0, low_open=True)


def read_restitution_csv(path, with_uncertainties=False):
    """(speeds, restitutions) from ``speed,restitution`` rows: optional header, # comments.

    A third column is the uncertainty of e (> 0; returned as a third array, NaN where empty,
    with ``with_uncertainties``); further columns are ignored.  e >= 1 is accepted (noise)."""
    from contact_sim.impact import MAX_POINTS   # the engine: after the arguments are parsed
    name = 'stdin' if path == '-' else path
    rows = []
    try:
        opened = contextlib.nullcontext(sys.stdin) if path == '-' else open(path, encoding='utf-8')
        with opened as source:
            for number, line in enumerate(iter(lambda: source.readline(MAX_LINE + 1), ''), 1):
                if len(line) > MAX_LINE:   # line by line, each bounded: bounded memory
                    raise InputError('data', name, 'data = {value} line %d is longer than %d '
                                     'characters: allowed rows "speed,restitution[,uncertainty]" '
                                     'of at most %d characters' % (number, MAX_LINE, MAX_LINE),
                                     value=repr(name))
                content = line.split('#', 1)[0].strip()
                if content:
                    rows.append((number, next(csv.reader(io.StringIO(content)))))
                if len(rows) > MAX_POINTS + 1:   # + a header
                    raise InputError('data', name, 'data = {value} has more than %d rows: '
                                     'allowed at most %d (speed, restitution) points'
                                     % (MAX_POINTS, MAX_POINTS), value=repr(name))
    except (OSError, UnicodeDecodeError) as error:
        reason = getattr(error, 'strerror', None) or str(error)
        raise ValueError(f'data = {name!r} cannot be read: {reason}') from None
    speeds, values, sigmas = [], [], []
    for index, (number, cells) in enumerate(rows):
        where = f'{name} line {number}'
        cells = [c.strip() for c in cells]
        if len(cells) < 2:
            raise ValueError(f'{where}: {len(cells)} columns in {",".join(cells)!r}: '
                             'allowed speed,restitution[,uncertainty,...]')
        if index == 0 and not any(_is_number(c) for c in cells):
            continue  # a header
        try:
            speeds.append(_cell('speed', cells[0]))
            values.append(_cell('restitution', cells[1]))
            sigmas.append(_cell('uncertainty', cells[2]) if len(cells) > 2 and cells[2]
                          else math.nan)
        except ValueError as error:
            raise ValueError(f'{where}: {error}') from None
    if not speeds:
        raise ValueError(f'data = {name!r} has no speed,restitution rows: allowed at least one')
    if with_uncertainties:
        return np.asarray(speeds), np.asarray(values), np.asarray(sigmas)
    return np.asarray(speeds), np.asarray(values)


def run(args):
    """Fit lambda per law to the data file and print the ranking and the points (and draw
    them with --plot); returns the exit status 0."""
    from contact_sim.impact import compare_laws, fit_damping
    speeds, measured, sigmas = read_restitution_csv(args.data, with_uncertainties=True)
    if np.all(np.isnan(sigmas)):
        sigmas = None
    elif np.any(np.isnan(sigmas)):
        raise ValueError(f'uncertainty is missing on line(s) of {args.data}: allowed an '
                         'uncertainty on every row or on none')
    laws = law_list(args, LAW_NAMES)
    setup = build_setup(args, laws, with_damping=False)
    if len(laws) == 1:
        fits = [fit_damping(laws[0], setup.contacts[laws[0].name].stiffness, setup.mass,
                            speeds, measured, args.confidence, args.loss, sigmas)]
    else:
        stiffness = {c.law: c.stiffness for c in setup.contacts.values()}
        fits = compare_laws(stiffness, setup.mass, speeds, measured,
                            laws=[c.law for c in setup.contacts.values()],
                            confidence=args.confidence, loss=args.loss, uncertainties=sigmas)
    source = 'stdin' if args.data == '-' else args.data
    print(f'# fit of lambda to {len(speeds)} point(s) of {source}, speeds '
          f'{speeds.min():g} to {speeds.max():g} m/s, least squares in e')
    print(f'# {describe_contact(setup, args)} ({setup.mass_source})')
    print('\n'.join(contact_lines(setup, show_damping=False)))
    print_fit_summary(fits, setup.radius, args.confidence)
    _print_fit_flags(fits[0], speeds, measured, sigmas)
    for fit in fits:
        print_fit_points(fit, speeds, measured)
    if args.plot:
        _plot(args, setup, fits, speeds, measured)
    return 0


def _print_fit_flags(fit, speeds, measured, sigmas):
    """e >= 1 points, the weighting and the robust loss's down-weighted points."""
    if sigmas is not None:
        print('# residuals weighted by 1/uncertainty (third column)')
    for i in fit.flagged:
        print(f'# note: point {i + 1} (speed {speeds[i]:g} m/s) has e = {measured[i]:g} >= 1: '
              'kept as measurement noise, no lambda matches it alone')
    if fit.loss != 'linear':
        down = [i for i, w in enumerate(fit.weights) if w < 0.5]
        print(f'# loss {fit.loss}: down-weighted points (weight < 0.5, {fit.law.name}): '
              + (', '.join(f'{i + 1} (speed {speeds[i]:g}, weight {fit.weights[i]:.2f})'
                           for i in down) or 'none'))


def print_fit_summary(fits, radius, confidence):
    """Per fit: lambda with its interval at ``confidence``, the rms residual, the spread of the
    pointwise lambdas and, with the equivalent ``radius`` R (m), lambda* = lambda / sqrt(R)."""
    level = f'{100 * confidence:g}%'
    if len(fits) > 1:
        print('# laws ranked by rms residual, best first')
    for fit in fits:
        law = fit.law
        low, high = fit.confidence_interval
        print(f'{law.name}: lambda = {fit.damping:.9e} {damping_unit(law)}')
        if math.isnan(low):
            why = 'every point has e >= 1: the elastic contact fits best' \
                if fit.damping == 0.0 else 'one point: no residual variance'
            print(f'  {level} confidence interval: n/a ({why})')
        else:
            print(f'  {level} confidence interval: [{low:.6e}, {high:.6e}]')
        print(f'  rms residual in e: {fit.rms_residual:.3e}')
        print(f'  pointwise lambda spread (max/min): {fit.pointwise_spread:.6f}')
        if radius is not None:
            print(f'  lambda* = lambda/sqrt(R) = {fit.damping / math.sqrt(radius):.9e} '
                  f'{damping_unit(law, extra=0.5)}')


def print_fit_points(fit, speeds, measured):
    """Per point: the data, the fitted e, the residual and the lambda that matches it alone."""
    law = fit.law
    print(f'# {law.name}: per point (lambda alone = the lambda that matches that point exactly)')
    print(f'# {"speed (m/s)":>12} {"e data":>10} {"e fitted":>10} {"residual":>11} '
          f'{"lambda alone (" + damping_unit(law) + ")":>26}')
    for v, e, r, lam in zip(speeds, measured, fit.residuals, fit.pointwise_damping):
        print(f'  {v:12.6g} {e:10.6f} {e + r:10.6f} {r:11.3e} {lam:26.6e}')


def _plot(args, setup, fits, speeds, measured):
    from contact_sim.impact import restitution
    dense = plotting.dense_speeds(speeds, log_speed=True)
    curves = {f'{fit.law.name}: \u03bb = {fit.damping:.4g} {damping_unit(fit.law)}, '
              f'rms {fit.rms_residual:.2g}':
              (dense, restitution(fit.contact(), setup.mass, dense)) for fit in fits}
    plotting.fit_figure(args.plot, (speeds, measured), curves,
                        f'Damping fit to {args.data}',
                        f'{describe_contact(setup, args)}, k {setup.stiffness_source}')
    print(f'# plot written to {args.plot}')
