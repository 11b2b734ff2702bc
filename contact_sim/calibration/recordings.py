"""Reading recorded impact times: plain CSV columns and phyphox "Acoustic Stopwatch" exports.

A recording is one or several sequences of impact (click) times in seconds, each with an optional
release height (m).  Accepted as they come from the phone or the lab:

* a phyphox CSV export read as is: the ``All`` sheet (``"Event time (s)"``, ``"Interval (s)"``:
  the interval of a row is the time to the next event, so a last event kept only as an interval
  is restored; an empty last interval is fine), the ``Multiple`` sheet (one run
  of six events per row: ``Start (s)``, ``Stop 1 (s)`` ... ``Stop 5 (s)``), or the zip of the CSV
  export (its ``All`` file is read);
* comma, semicolon or tab separators, decimal point or decimal comma, quoted headers;
* several runs pasted side by side: every time column is one sequence (empty cells end a column),
  or only the columns chosen (by header or number); a column that numbers the events (a header
  ``index``, ``nr``, ``n``, ... or the values 0, 1, 2, ...) is not a sequence of times;
* a release height in a column header or a file name (``h=0.8``, ``height = 80 cm``, ``0.8m``,
  ``1,5 m``; a number glued to a word is not one: ``Lancio1,10cm`` is 0.10 m), one in the file
  name for every run of the file or one per run in order, or given separately (``--height`` on
  the command line);
* phyphox workbooks (``.xlsx`` by openpyxl, ``.xls`` by xlrd): the ``All`` sheet, read like
  its CSV;
* a long table of trials (``group_by``): one sequence per value of a trial column;
* text after ``#`` on a line is a comment.
"""
import csv
import io
import os
import re
import zipfile
from dataclasses import dataclass

import numpy as np

from contact_sim.validation import InputError, require_positive, require_real_array

MAX_CLICKS = 5000          # impact times per sequence and in all (a fit of 2000 takes ~14 s)
MAX_SEQUENCES = 200        # sequences in one fit (each adds its own start and release)
MAX_ROWS = 100_000         # lines of a CSV file read for impact times
MAX_BYTES = 64 * 2**20     # size of a file read for impact times
MAX_TIMES = MAX_CLICKS     # (the name the library layer refuses a sequence by)


@dataclass(frozen=True)
class ImpactTimes:
    """One recorded sequence: times (s, increasing), optional release height (m) and a name."""

    times: np.ndarray
    height: float = None
    name: str = ''

    def __post_init__(self):
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
    keyed = list(_HEIGHT_KEY.finditer(label))
    found = keyed or list(_HEIGHT.finditer(label))
    return [float(m.group(1).replace(',', '.')) * _UNITS[(m.group(2) or 'm').lower()]
            for m in found]


def height_from_label(label):
    """The first release height (m) named in a column header or file name, or ``None``
    (``heights_from_label``)."""
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


def _read_text(path):
    name = str(path)
    if name.lower().endswith('.ods'):
        raise ValueError(f'data = {name!r} is an OpenDocument workbook: allowed CSV, .xlsx or '
                         '.xls; save its All sheet as CSV')
    if name.lower().endswith('.zip'):
        try:
            with zipfile.ZipFile(path) as z:
                members = [m for m in z.namelist() if m.lower().endswith('.csv')]
                texts = {m: z.read(m).decode('utf-8-sig') for m in members}
        except (OSError, zipfile.BadZipFile, UnicodeDecodeError) as error:
            raise ValueError(f'data = {name!r} cannot be read: {error}') from None
        if not members:
            raise ValueError(f'data = {name!r} holds no CSV file: allowed a phyphox CSV export '
                             '(zip of CSV files)')
        # the All sheet: by its name, else the file with the most lines (it holds every event)
        named = [m for m in members
                 if re.search(r'\ball\b', m.rsplit('/', 1)[-1], re.IGNORECASE)]
        return texts[named[0] if named else max(members, key=lambda m: texts[m].count('\n'))]
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise InputError('data', name, '{n[data]} = {value} holds %d bytes: allowed at most '
                             '%d (%d MB) for a file of impact times' % (size, MAX_BYTES,
                                                                       MAX_BYTES // 2**20))
        with open(path, encoding='utf-8-sig') as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as error:
        reason = getattr(error, 'strerror', None) or str(error)
        raise ValueError(f'data = {name!r} cannot be read: {reason}') from None


def _read_workbook(path):
    """The rows (lists of cell texts) of a workbook's ``All`` sheet (else its longest sheet):
    ``.xlsx`` by openpyxl, ``.xls`` by xlrd, both imported only here."""
    name = str(path)
    try:
        if name.lower().endswith('.xlsx'):
            import openpyxl
            book = openpyxl.load_workbook(path, read_only=True, data_only=True)
            sheets = {ws.title: [list(r) for r in ws.iter_rows(values_only=True)]
                      for ws in book.worksheets}
            book.close()
        else:
            import xlrd
            book = xlrd.open_workbook(path)
            sheets = {sh.name: [sh.row_values(i) for i in range(sh.nrows)]
                      for sh in book.sheets()}
    except ImportError as error:
        raise ValueError(f'data = {name!r} is a workbook and {error.name} is not installed: '
                         'pip install openpyxl xlrd (or save the All sheet as CSV)') from None
    except Exception as error:      # each library has its own errors for a bad file
        raise ValueError(f'data = {name!r} cannot be read as a workbook: {error}') from None
    named = [n for n in sheets if re.search(r'\ball\b', n, re.IGNORECASE)]
    rows = sheets[named[0]] if named else max(sheets.values(), key=len, default=[])
    if len(rows) > MAX_ROWS:
        raise InputError('data', name, '{n[data]} = {value} has %d rows: allowed at most %d'
                         % (len(rows), MAX_ROWS))
    return [['' if c is None else repr(float(c)) if isinstance(c, (int, float)) else str(c)
             for c in row] for row in rows]


def parse_impact_times(text, source='data', columns=None, group_by=None):
    """Sequences (list of ``ImpactTimes``) from the text of a CSV file; see module doc.

    Parameters
    ----------
    text : str
        The file's text.
    source : str
        Its name, in the sequences' names and the messages.
    columns : list of str, optional
        The columns to read (headers or numbers from 1); default every time column.
    group_by : str, optional
        A trial column (header or number from 1) of a long table: one sequence per value, in
        the order they come, its times from the first of ``columns`` (else the first time
        column); a height in the value (``80cm``) goes to its sequence.

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
    delimiter, decimal_comma = _dialect(lines)
    rows = [[c.strip() for c in next(csv.reader(io.StringIO(ln), delimiter=delimiter))]
            for ln in lines if ln.strip()]
    return _parse_rows(rows, decimal_comma, source, columns, group_by)


def _parse_rows(rows, decimal_comma, source, columns, group_by):
    """``parse_impact_times`` on rows of cell texts."""
    rows = [[c.strip() for c in row] for row in rows if any(c.strip() for c in row)]
    if not rows:
        raise ValueError(f'{source} has no impact times: allowed one column of times (s) per '
                         'sequence, or a phyphox Acoustic Stopwatch export')
    header = None
    if not any(_number(c, decimal_comma) is not None for c in rows[0]):
        header, rows = rows[0], rows[1:]
    width = max(len(r) for r in rows) if rows else 0
    labels = list(header or []) + [''] * (width - len(header or []))
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
        return _grouped(rows, labels, width, decimal_comma, source, columns, group_by)
    chosen = _selected(columns, labels, width, source) if columns else [
        i for i in range(width)
        if not _INTERVAL.search(labels[i]) and not _INDEX.search(labels[i])]
    sequences = []
    for i in chosen:
        values, last_row = _column(rows, i, decimal_comma)
        if not values or (not columns and _counts_events(values)):
            continue
        # the interval beside a time column is the time to the next event: a last event kept
        # only as an interval is restored
        if i + 1 < width and _INTERVAL.search(labels[i + 1]):
            cells = rows[last_row]
            last = _number(cells[i + 1], decimal_comma) if i + 1 < len(cells) else None
            if last is not None and last > 0.0:
                values.append(values[-1] + last)
        label = labels[i] or f'column {i + 1}'
        sequences.append(ImpactTimes(np.array(values), height_from_label(labels[i]),
                                     f'{source}: {label}'))
    if not sequences:
        raise ValueError(f'{source} has no impact times: allowed one column of times (s) per '
                         'sequence, or a phyphox Acoustic Stopwatch export')
    return sequences


def _grouped(rows, labels, width, decimal_comma, source, columns, group_by):
    """One sequence per value of the trial column ``group_by``, in the order they come: the
    times of its rows in the time column (``columns``' first, else the first time column)."""
    (key,) = _selected([group_by], labels, width, source)
    if columns:
        times = _selected(columns[:1], labels, width, source)[0]
    else:
        candidates = [i for i in range(width) if i != key and not _INTERVAL.search(labels[i])
                      and not _INDEX.search(labels[i])
                      and any(_number(r[i], decimal_comma) is not None
                              for r in rows if i < len(r))]
        if not candidates:
            raise ValueError(f'{source} has no time column beside the trial column '
                             f'{group_by!r}: allowed a table of trial and time columns')
        timed = [i for i in candidates if _TIME.search(labels[i])]
        times = (timed or candidates)[0]
    groups = {}
    for row in rows:
        if key >= len(row) or not row[key] or times >= len(row):
            continue
        t = _number(row[times], decimal_comma)
        if t is not None:
            groups.setdefault(row[key], []).append(t)
    if not groups:
        raise ValueError(f'{source} has no impact times grouped by {group_by!r}')
    label = labels[key] or f'column {key + 1}'
    return [ImpactTimes(np.array(values), height_from_label(value),
                        f'{source}: {label} = {value}') for value, values in groups.items()]


def _column(rows, i, decimal_comma):
    """The numbers of column ``i`` from its first one to the first empty cell after it, and
    the row of the last one."""
    values, last_row = [], None
    for n, row in enumerate(rows):
        x = _number(row[i], decimal_comma) if i < len(row) else None
        if x is None:
            if values:
                break          # an empty cell ends a column pasted beside a longer one
            continue
        values.append(x)
        last_row = n
    return values, last_row


def _counts_events(values):
    """Whether a column counts the events (0, 1, 2, ... or 1, 2, 3, ...) instead of timing
    them: bounce flights shrink, they are never all one second long."""
    return len(values) >= 2 and values[0] in (0.0, 1.0) and bool(np.all(np.diff(values) == 1.0))


def _selected(columns, labels, width, source):
    """Column positions (from 0) of ``columns``: each a header (case and spaces aside) or a
    number from 1."""
    names = [lab.strip().lower() for lab in labels]
    chosen = []
    for wanted in columns:
        text = str(wanted).strip()
        if text.lower() in names:
            chosen.append(names.index(text.lower()))
        elif text.isdigit() and 1 <= int(text) <= width:
            chosen.append(int(text) - 1)
        else:
            headers = ', '.join(repr(lab) for lab in labels if lab) or 'none'
            raise ValueError(f'column = {text!r} is not in {source}: allowed a header '
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


def read_impact_times(path, columns=None, group_by=None):
    """Sequences of impact times from a CSV file or phyphox export (``.csv``, ``.zip`` of CSV,
    ``.xlsx`` or ``.xls``: the workbook's ``All`` sheet, else its longest).

    Release heights in the file name go to the sequences without a height of their own: one
    height to every run, or as many heights as runs, in order.

    Parameters
    ----------
    path : str or Path
    columns, group_by : optional
        The columns to read and the trial column (``parse_impact_times``).

    Returns
    -------
    list of ImpactTimes

    Raises
    ------
    ValueError
        If the file cannot be read, holds no impact times, or its name holds a number of
        heights that is neither one nor the number of runs.
    """
    if str(path).lower().endswith(('.xlsx', '.xls')):
        sequences = _parse_rows(_read_workbook(path), False, str(path), columns, group_by)
    else:
        sequences = parse_impact_times(_read_text(path), source=str(path), columns=columns,
                                       group_by=group_by)
    heights = heights_from_label(str(path).replace('\\', '/').rsplit('/', 1)[-1])
    if len(heights) == 1:
        heights = heights * len(sequences)
    if heights and len(heights) != len(sequences):
        raise ValueError(f'data = {str(path)!r} names {len(heights)} heights for '
                         f'{len(sequences)} runs: allowed one height, or one per run in order')
    return [ImpactTimes(s.times, h, s.name) if heights and s.height is None else s
            for s, h in zip(sequences, heights or [None] * len(sequences))]
