"""Reading recorded impact times: plain CSV columns and phyphox "Acoustic Stopwatch" exports.

A recording is one or several sequences of impact (click) times in seconds, each with an optional
release height (m).  Accepted as they come from the phone or the lab:

* a phyphox CSV export read as is: the ``All`` sheet (``"Event time (s)"``, ``"Interval (s)"``:
  the interval of a row is the time to the next event, so a last event kept only as an interval
  is restored), the ``Multiple`` sheet (one run of six events per row: ``Start (s)``, ``Stop 1
  (s)`` ... ``Stop 5 (s)``), or the zip of the CSV export (its ``All`` file is read);
* comma, semicolon or tab separators, decimal point or decimal comma, quoted headers;
* several runs side by side: every time column is one sequence (empty cells end a block of it),
  or only the columns chosen (header or number); a column that numbers the events (``index``,
  ``nr``, ``n``, ... or the values 0, 1, 2, ...) is not one;
* a release height in a column header or a file name (``h=0.8``, ``height = 80 cm``, ``0.8m``,
  ``1,5 m``; ``Lancio1,10cm`` is 0.10 m), one in the file name for every run of the file or one
  per run in order, or given separately (``--height`` on the command line);
* workbooks (``.xlsx``, ``.xls``): every sheet that holds runs (``workbooks``), each read like
  a CSV; a phyphox export's ``All`` sheet (its ``Simple`` and ``Multiple`` repeat it);
* a long table of trials (``group_by``): one sequence per combination of trial columns'
  values; a row filter (``where``) for one ball of a combined table (``#`` begins a comment).
"""
import csv
import io
import os
import re
from dataclasses import dataclass

import numpy as np

from contact_sim.calibration.workbooks import MAX_BYTES, read_text as _read_text  # noqa: F401
from contact_sim.validation import InputError, require_positive, require_real_array

MAX_CLICKS = 5000          # impact times per sequence and in all (a fit of 2000 takes ~14 s)
MAX_SEQUENCES = 200        # sequences in one fit (each adds its own start and release)
MAX_ROWS = 100_000         # lines of a CSV file read for impact times
MAX_TIMES = MAX_CLICKS     # (the name the library layer refuses a sequence by)
MAX_LINE = 100_000         # characters in one line of a CSV file (csv's field limit: 131072)


@dataclass(frozen=True)
class ImpactTimes:
    """One recorded sequence: times (s, increasing), optional release height (m) and a name."""

    times: np.ndarray
    height: float = None
    name: str = ''

    def __post_init__(self):
        if self.name is not None and not isinstance(self.name, str):
            raise InputError('name', self.name, '{n[name]} = {value} is not text: allowed a str')
        where = (self.name or 'sequence').replace('{', '{{').replace('}', '}}')
        try:
            t = require_real_array('times', self.times, MAX_CLICKS)
        except InputError as error:
            raise InputError('times', error.value, where + ': ' + error.template,
                             **error.params) from None
        if t.ndim != 1:
            raise InputError('times', t.shape, where + ': {n[times]} has the shape {value}: '
                             'allowed one sequence of times, a 1-D array', value=str(t.shape))
        if t.size < 3:
            raise InputError('times', t.size, where + ': {value} impact time(s): allowed at '
                             'least 3 (two bounce flights)', value=str(t.size))
        if np.any(np.diff(t) <= 0.0):
            i = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
            raise InputError('times', float(t[i + 1]), where + ': {n[times]}[%d] = {value} is '
                             'out of range: allowed {n[times]}[%d] > {n[times]}[%d] = %r '
                             '(increasing)' % (i + 1, i + 1, i, float(t[i])))
        object.__setattr__(self, 'times', t)
        if self.height is not None:
            object.__setattr__(self, 'height', require_positive('height', self.height))


# a number not glued to a word before it ('Lancio1,10cm' is run 1 from 10 cm, not 1.10 cm),
# with a decimal point or comma, then its unit
_HEIGHT = re.compile(r'(?<![^\W_])(\d+(?:[.,]\d+)?)\s*(mm|cm|m)(?![^\W_])', re.IGNORECASE)
_HEIGHT_KEY = re.compile(r'(?<![^\W_])(?:h|height|hoehe|höhe|altura|hauteur|altezza)\s*[=:]\s*'
                         r'(\d+(?:[.,]\d+)?)\s*(mm|cm|m)?(?![^\W_])', re.IGNORECASE)
_UNITS = {'mm': 1e-3, 'cm': 1e-2, 'm': 1.0}
# columns that number the events rather than time them
_INDEX = re.compile(r'(?<![^\W_])(index|idx|nr|no|number|count|n|#)(?![^\W_])', re.IGNORECASE)
_TIME = re.compile(r'time|zeit|tempo|temps|tiempo|\(s\)', re.IGNORECASE)
_INTERVAL = re.compile(r'interval|difference|differenz|interv|abstand', re.IGNORECASE)


def heights_from_label(label):
    """Every release height (m) named in a column header or file name, in order.

    Parameters
    ----------
    label : str
        A header or a file name: ``h=0.8``, ``80cm``, ``1,5 m``, ``Lancio1,10cm``.

    Returns
    -------
    list of float
        The heights in m (a key ``h=`` without a unit is in m); empty if none.

    Examples
    --------
    >>> from contact_sim.calibration import heights_from_label
    >>> heights_from_label('Lancio1,10cm.csv')
    [0.1]
    >>> heights_from_label('drops_80cm_1,2m')
    [0.8, 1.2]
    """
    if not isinstance(label, str):
        raise InputError('label', label, '{n[label]} = {value} is not text: allowed a column '
                         'header or a file name (str)')
    keyed = list(_HEIGHT_KEY.finditer(label))
    found = keyed or list(_HEIGHT.finditer(label))
    return [float(m.group(1).replace(',', '.')) * _UNITS[(m.group(2) or 'm').lower()]
            for m in found]


def height_from_label(label):
    """The first release height (m) in a label, or ``None`` (``heights_from_label``)."""
    heights = heights_from_label(label)
    return heights[0] if heights else None


def _number(cell, decimal_comma):
    text = cell.strip().strip('"').strip()
    if not text:
        return None
    if decimal_comma:
        text = text.replace('.', '').replace(',', '.') if text.count(',') == 1 \
            else text.replace(',', '.')
    try:
        return float(text)
    except ValueError:
        return None


def _dialect(lines):
    sample = [ln for ln in lines if ln.strip()][:20]
    counts = {d: sum(ln.count(d) for ln in sample) for d in (';', '\t', ',')}
    if counts['\t'] > 0:
        delimiter = '\t'
    elif counts[';'] > 0:
        delimiter = ';'
    else:
        delimiter = ','
    decimal_comma = delimiter != ',' and any(re.search(r'\d,\d', ln) for ln in sample)
    return delimiter, decimal_comma


def parse_impact_times(text, source='data', columns=None, group_by=None, where=None,
                       notes=None):
    """Sequences (list of ``ImpactTimes``) from the text of a CSV file; see module doc.

    Parameters
    ----------
    text : str
        The file's text.
    source : str
        Its name, in the sequences' names and the messages.
    columns : list of str, optional
        The columns to read (headers or numbers from 1); default every time column.
    group_by : str or list of str, optional
        The trial columns (headers or numbers from 1; several as a list or separated by
        commas: ``'ball,height_cm,trial'``) of a long table: one sequence per combination of
        their values, in the order they come, its times from the first of ``columns`` (else
        the first time column); a height in a value (``80cm``, or a number under a header
        with a unit such as ``height_cm``) goes to its sequence.
    where : dict, optional
        Read only the rows whose column (header or number from 1) holds the value given
        (``{'ball': 'golf'}``; text compared without case, numbers as numbers).
    notes : list, optional
        Receives a line for each thing found and not read (a column that is not times, a
        block of times after a gap read as a run of its own, rows filtered out).

    Returns
    -------
    list of ImpactTimes

    Raises
    ------
    ValueError
        If no impact times are found, a column asked for is not there, or a sequence is bad.
    """
    if not isinstance(text, str):
        raise InputError('text', text, '{n[text]} = {value} is not text: allowed the text of a '
                         'CSV file (str)')
    lines = [ln.split('#', 1)[0] for ln in text.splitlines()]
    if len(lines) > MAX_ROWS:
        raise InputError('data', source, '{n[data]} = {value} has %d lines: allowed at most %d'
                         % (len(lines), MAX_ROWS))
    if (longest := max((len(ln) for ln in lines), default=0)) > MAX_LINE:
        raise InputError('data', source, '{n[data]} = {value} has a line of %d characters: '
                         'allowed at most %d' % (longest, MAX_LINE))
    delimiter, decimal_comma = _dialect(lines)
    try:
        rows = [[c.strip() for c in next(csv.reader(io.StringIO(ln), delimiter=delimiter))]
                for ln in lines if ln.strip()]
    except csv.Error as error:
        raise InputError('data', source, '{n[data]} = {value} is not a readable CSV file '
                         '(%s): allowed a table of impact times' % error) from None
    return _parse_rows(rows, decimal_comma, source, columns, group_by, where, notes)


class NoTimes(ValueError):
    """A table (a sheet) that holds no impact times, or not the columns asked for."""


def _parse_rows(rows, decimal_comma, source, columns, group_by, where, notes, some=False):
    """``parse_impact_times`` on rows of cell texts (``some``: of ``columns``, those there)."""
    notes = [] if notes is None else notes
    if columns is not None and (isinstance(columns, (str, bytes))
                                or not hasattr(columns, '__iter__')):
        raise InputError('column', columns, '{n[column]} = {value} is not a list: allowed a '
                         'list of headers or numbers from 1')
    rows = [[c.strip() for c in row] for row in rows]     # empty rows end blocks of times
    rows = rows[next((n for n, row in enumerate(rows) if any(row)), len(rows)):]
    if not rows:
        raise NoTimes(f'{source} has no impact times: allowed one column of times (s) per '
                      'sequence, or a phyphox Acoustic Stopwatch export')
    header = None
    if not any(_number(c, decimal_comma) is not None for c in rows[0]):
        header, rows = rows[0], rows[1:]
    width = max(len(r) for r in rows) if rows else 0
    labels = list(header or []) + [''] * (width - len(header or []))
    if where:
        rows = _filtered(rows, labels, width, decimal_comma, source, where, notes)
    lower = [lab.lower() for lab in labels]
    if header and any(re.match(r'\s*start\b', c) for c in lower) \
            and any(re.match(r'\s*stop\s*1\b', c) for c in lower):
        # phyphox "Multiple": one run of up to six events per row
        columns = [i for i, c in enumerate(lower) if re.match(r'\s*(start|stop)', c)]
        sequences = []
        for number, row in enumerate(rows, 1):
            t = [_number(row[i], decimal_comma) for i in columns if i < len(row)]
            t = [x for x in t if x is not None]
            if t:
                sequences.append(ImpactTimes(np.array(t), None, f'{source} row {number}'))
        return sequences
    if group_by is not None:
        return _grouped(rows, labels, width, decimal_comma, source, columns, group_by, notes)
    chosen = _selected(columns, labels, width, source, some) if columns else [
        i for i in range(width) if not _INTERVAL.search(labels[i])]
    timed = [i for i in chosen if _TIME.search(labels[i])]
    if not columns and timed and len(timed) < len(chosen):   # only the columns headed as times
        others = [labels[i] or f'column {i + 1}' for i in chosen if i not in timed]
        notes.append(f'{source}: {", ".join(repr(o) for o in others)} not read: not headed as '
                     'times beside columns that are (--column picks any; --group-by splits a '
                     'table of trials)')
        chosen = timed
    sequences = []
    for i in chosen:
        label = labels[i] or f'column {i + 1}'
        blocks = _column(rows, i, decimal_comma)
        if not columns and _INDEX.search(labels[i]) or not columns and blocks \
                and _counts_events(blocks[0][0]):
            notes.append(f'{source}: {label!r} not read: it numbers the events')
            continue
        if not blocks:
            if any(i < len(r) and r[i] for r in rows):
                notes.append(f'{source}: {label!r} not read: no numbers in it')
            continue
        for b, (values, last_row) in enumerate(blocks):
            # the interval beside a time column is the time to the next event: a last event
            # kept only as an interval is restored
            if i + 1 < width and _INTERVAL.search(labels[i + 1]):
                cells = rows[last_row]
                last = _number(cells[i + 1], decimal_comma) if i + 1 < len(cells) else None
                if last is not None and last > 0.0:
                    values.append(values[-1] + last)
            name = f'{source}: {label}' + (f' (block {b + 1}, after an empty cell)'
                                            if len(blocks) > 1 else '')
            try:
                sequences.append(ImpactTimes(np.array(values), height_from_label(labels[i]),
                                             name))
            except InputError as error:
                if 'increasing' not in error.template:
                    raise
                raise InputError(error.field, error.value, error.template + '; several runs '
                                 'in one column? --group-by (group_by) splits a table of '
                                 'trials', **error.params) from None
        if len(blocks) > 1:
            notes.append(f'{source}: {label!r} holds {len(blocks)} blocks of times between '
                         'empty cells: each read as a run')
    if not sequences:
        raise NoTimes(f'{source} has no impact times: allowed one column of times (s) per '
                      'sequence, or a phyphox Acoustic Stopwatch export')
    return sequences


def _same(cell, wanted, decimal_comma):
    """Whether a cell holds the value ``wanted``: numbers as numbers, text without case."""
    a, b = _number(cell, decimal_comma), _number(str(wanted), decimal_comma)
    return a == b if a is not None and b is not None else \
        cell.strip().lower() == str(wanted).strip().lower()


def _filtered(rows, labels, width, decimal_comma, source, where, notes):
    """The rows whose columns hold the values of ``where`` (column -> value)."""
    if not isinstance(where, dict):
        raise InputError('where', where, '{n[where]} = {value} is not a mapping: allowed '
                         'column -> value, e.g. {"ball": "golf"}')
    tests = [(_selected([col], labels, width, source)[0], value)
             for col, value in where.items()]
    kept = [r for r in rows if all(i < len(r) and _same(r[i], value, decimal_comma)
                                   for i, value in tests)]
    wanted = ', '.join(f'{col}={value}' for col, value in where.items())
    if not kept:
        i, _ = tests[0]
        seen = sorted({r[i] for r in rows if i < len(r) and r[i]})
        raise NoTimes(f'where {wanted} matches no row of {source}: allowed a value of the '
                      f'column ({", ".join(seen[:12]) or "none"})')
    notes.append(f'{source}: {len(kept)} of {len(rows)} rows read (where {wanted})')
    return kept


def _group_keys(group_by):
    keys = group_by.split(',') if isinstance(group_by, str) else list(group_by) \
        if isinstance(group_by, (list, tuple)) else [group_by]
    keys = [str(k).strip() for k in keys]
    if not keys or not all(keys):
        raise InputError('group_by', group_by, '{n[group_by]} = {value} names no column: '
                         'allowed headers or numbers from 1, separated by commas',
                         value=repr(group_by))
    return keys


_UNIT_HEADER = re.compile(r'(?<![^\W_])(?:h|height|hoehe|höhe|altura|hauteur|altezza)'
                          r'[\s_(\[]*(mm|cm|m)\b', re.IGNORECASE)


def _group_height(header, value, decimal_comma):
    """A height in a group's value: ``80cm`` itself, or a number under ``height_cm``."""
    unit = _UNIT_HEADER.search(header)
    number = _number(value, decimal_comma)
    if unit and number is not None and number > 0.0:
        return number * _UNITS[unit.group(1).lower()]
    return height_from_label(value)


def _grouped(rows, labels, width, decimal_comma, source, columns, group_by, notes):
    """One sequence per combination of the values of the trial columns ``group_by``, in the
    order they come: the times of its rows in the time column (``columns``' first, else the
    first time column)."""
    keys = _selected(_group_keys(group_by), labels, width, source)
    if columns:
        times = _selected(columns[:1], labels, width, source)[0]
    else:
        candidates = [i for i in range(width) if i not in keys
                      and not _INTERVAL.search(labels[i]) and not _INDEX.search(labels[i])
                      and any(_number(r[i], decimal_comma) is not None
                              for r in rows if i < len(r))]
        if not candidates:
            raise NoTimes(f'{source} has no time column beside the trial column(s) '
                          f'{group_by!r}: allowed a table of trial and time columns')
        timed = [i for i in candidates if _TIME.search(labels[i])]
        times = (timed or candidates)[0]
    groups, skipped = {}, 0
    for row in rows:
        if any(k >= len(row) or not row[k] for k in keys) or times >= len(row):
            skipped += bool(any(c for c in row))
            continue
        t = _number(row[times], decimal_comma)
        if t is not None:
            groups.setdefault(tuple(row[k] for k in keys), []).append(t)
        elif row[times]:
            skipped += 1
    if not groups:
        raise NoTimes(f'{source} has no impact times grouped by {group_by!r}')
    if skipped:
        notes.append(f'{source}: {skipped} row(s) not read: an empty trial cell or no number '
                     f'in the time column {labels[times] or times + 1!r}')
    names = [labels[k] or f'column {k + 1}' for k in keys]
    out = []
    for values, t in groups.items():
        heights = [h for h in (_group_height(labels[k], v, decimal_comma)
                               for k, v in zip(keys, values)) if h is not None]
        name = ', '.join(f'{n} = {v}' for n, v in zip(names, values))
        out.append(ImpactTimes(np.array(t), heights[0] if heights else None,
                               f'{source}: {name}'))
    return out


def _column(rows, i, decimal_comma):
    """The blocks of numbers of column ``i`` between empty cells: (values, row of the last)."""
    blocks, values, last_row = [], [], None
    for n, row in enumerate(rows):
        x = _number(row[i], decimal_comma) if i < len(row) else None
        if x is None:
            if values:
                blocks.append((values, last_row))
                values = []
            continue
        values.append(x)
        last_row = n
    if values:
        blocks.append((values, last_row))
    return blocks


def _counts_events(values):
    """Whether a column counts the events (0, 1, 2, ... or 1, 2, 3, ...) instead of timing
    them: bounce flights shrink, they are never all one second long."""
    return len(values) >= 2 and values[0] in (0.0, 1.0) and bool(np.all(np.diff(values) == 1.0))


def _selected(columns, labels, width, source, some=False):
    """Column positions (from 0) of ``columns``: each a header (case and spaces aside) or a
    number from 1 (with ``some``, those of them there are, at least one)."""
    names, chosen, missing = [lab.strip().lower() for lab in labels], [], []
    for wanted in columns:
        text = str(wanted).strip()
        if text.lower() in names:
            chosen.append(names.index(text.lower()))
        elif text.isdigit() and 1 <= int(text) <= width:
            chosen.append(int(text) - 1)
        else:
            missing.append(text)
    if missing and not (some and chosen):
        headers = ', '.join(repr(lab) for lab in labels if lab) or 'none'
        raise NoTimes(f'column = {missing[0]!r} is not in {source}: allowed a header '
                      f'({headers}) or a number 1 to {width}')
    return chosen


def require_sizes(sequences):
    """Refuse more than ``MAX_SEQUENCES`` sequences or ``MAX_CLICKS`` impact times in all.

    Raises
    ------
    InputError
        Naming ``sequences`` and the limit.
    """
    total = sum(s.times.size for s in sequences)
    if len(sequences) > MAX_SEQUENCES:
        raise InputError('sequences', len(sequences), '{n[sequences]} holds {value} sequences: '
                         'allowed at most %d in one fit' % MAX_SEQUENCES)
    if total > MAX_CLICKS:
        raise InputError('sequences', total, '{n[sequences]} hold {value} impact times in all: '
                         'allowed at most %d in one fit' % MAX_CLICKS)


def read_impact_times(path, columns=None, group_by=None, where=None, notes=None, named=True):
    """Sequences of impact times from a CSV file or phyphox export (``.csv``, ``.zip`` of CSV,
    ``.xlsx`` or ``.xls``: every sheet that holds runs, ``workbooks.sheets_to_read``).

    Release heights in the file name go to the sequences without a height of their own: one
    height to every run, or as many heights as runs, in order.

    Parameters
    ----------
    path : str or Path
    columns, group_by, where : optional
        The columns to read, the trial columns and the row filter (``parse_impact_times``).
    notes : list, optional
        Receives a line for every sheet, column or row found and not read, and why.
    named : bool, optional
        False: the file name's heights are neither read nor checked (the caller gives them).

    Returns
    -------
    list of ImpactTimes

    Raises
    ------
    InputError, ValueError
        If the file cannot be read, holds no impact times, or its name holds a number of
        heights that is neither one nor the number of runs.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputError('data', path, '{n[data]} = {value} is not a file name: allowed a path')
    notes, name = [] if notes is None else notes, str(path)
    if name.lower().endswith(('.xlsx', '.xls')):
        from contact_sim.calibration.workbooks import sheets_to_read, workbook_sheets
        read, left = sheets_to_read(workbook_sheets(path))
        sequences, empty, used, first = [], [], [], len(notes)
        for sheet, rows in read:
            source = f'{name} [{sheet}]' if len(read) > 1 else name
            try:
                found = _parse_rows(rows, False, source, columns, group_by, where, notes, True)
            except NoTimes as error:
                empty.append(str(error))
                continue
            used.append(sheet)
            height = heights_from_label(sheet)      # a sheet per height: '80cm'
            sequences += [ImpactTimes(s.times, height[0], s.name)
                          if len(height) == 1 and s.height is None else s for s in found]
        if not sequences:
            raise ValueError('; '.join(empty) or f'{name} has no sheet of impact times')
        left += empty
        words = ', '.join(repr(s) for s in used)
        notes.insert(first, f'{name}: {len(sequences)} run(s) read from sheet(s) {words}'
                     + (f'; not read: {"; ".join(left)}' if left else ''))
    else:
        sequences = parse_impact_times(_read_text(path), source=name, columns=columns,
                                       group_by=group_by, where=where, notes=notes)
    heights = heights_from_label(name.replace('\\', '/').rsplit('/', 1)[-1] if named else '')
    if len(heights) == 1:
        heights = heights * len(sequences)
    if heights and len(heights) != len(sequences):
        raise ValueError(f'data = {name!r} names {len(heights)} heights for '
                         f'{len(sequences)} runs: allowed one height, or one per run in order')
    return [ImpactTimes(s.times, h, s.name) if heights and s.height is None else s
            for s, h in zip(sequences, heights or [None] * len(sequences))]
