"""Reading recorded impact times: plain CSV columns and phyphox "Acoustic Stopwatch" exports.

A recording is one or several sequences of impact (click) times in seconds, each with an optional
release height (m).  Accepted as they come from the phone or the lab:

* a phyphox CSV export read as is: the ``All`` sheet (``"Event time (s)"``, ``"Interval (s)"``;
  the interval column is ignored, an empty last interval is fine), the ``Multiple`` sheet (one run
  of six events per row: ``Start (s)``, ``Stop 1 (s)`` ... ``Stop 5 (s)``), or the zip of the CSV
  export (its ``All`` file is read);
* comma, semicolon or tab separators, decimal point or decimal comma, quoted headers;
* several runs pasted side by side: every time column is one sequence (empty cells end a column);
* a release height in a column header (``h=0.8``, ``height = 80 cm``, ``0.8m``), or given
  separately (``--height`` on the command line);
* text after ``#`` on a line is a comment.
"""
import csv
import io
import re
import zipfile
from dataclasses import dataclass

import numpy as np

from contact_sim.validation import require_positive


@dataclass(frozen=True)
class ImpactTimes:
    """One recorded sequence: times (s, increasing), optional release height (m) and a name."""

    times: np.ndarray
    height: float = None
    name: str = ''

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float).ravel()
        if t.size < 3:
            raise ValueError(f'{self.name or "sequence"}: {t.size} impact time(s): allowed at '
                             'least 3 (two bounce flights)')
        if not np.all(np.isfinite(t)):
            raise ValueError(f'{self.name or "sequence"}: impact times must be finite numbers')
        if np.any(np.diff(t) <= 0.0):
            i = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
            raise ValueError(f'{self.name or "sequence"}: times[{i + 1}] = {t[i + 1]!r} is out of '
                             f'range: allowed times[{i + 1}] > times[{i}] = {t[i]!r} (increasing)')
        object.__setattr__(self, 'times', t)
        if self.height is not None:
            object.__setattr__(self, 'height', require_positive('height', self.height))


_HEIGHT = re.compile(r'(?:\b(?:h|height|hoehe|höhe|altura|hauteur)\s*[=:]?\s*)?'
                     r'(\d+(?:[.,]\d+)?)\s*(mm|cm|m)\b', re.IGNORECASE)
_HEIGHT_KEY = re.compile(r'\b(?:h|height|hoehe|höhe|altura|hauteur)\s*[=:]\s*(\d+(?:[.,]\d+)?)'
                         r'\s*(mm|cm|m)?', re.IGNORECASE)


def height_from_label(label):
    """A release height (m) named in a column header or file name, or ``None``."""
    m = _HEIGHT_KEY.search(label) or _HEIGHT.search(label)
    if not m:
        return None
    value = float(m.group(1).replace(',', '.'))
    unit = (m.group(2) or 'm').lower()
    return value * {'mm': 1e-3, 'cm': 1e-2, 'm': 1.0}[unit]


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
    if name.lower().endswith(('.xls', '.xlsx', '.ods')):
        raise ValueError(f'data = {name!r} is a spreadsheet workbook: allowed CSV; export the '
                         'phyphox data as CSV (or save its All sheet as CSV)')
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
        with open(path, encoding='utf-8-sig') as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as error:
        reason = getattr(error, 'strerror', None) or str(error)
        raise ValueError(f'data = {name!r} cannot be read: {reason}') from None


def parse_impact_times(text, source='data'):
    """Sequences (list of ``ImpactTimes``) from the text of a CSV file; see module doc."""
    lines = [ln.split('#', 1)[0] for ln in text.splitlines()]
    delimiter, decimal_comma = _dialect(lines)
    rows = [[c.strip() for c in next(csv.reader(io.StringIO(ln), delimiter=delimiter))]
            for ln in lines if ln.strip()]
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
    # time columns: everything but interval/difference columns
    skip = {i for i, c in enumerate(lower)
            if re.search(r'interval|difference|differenz|interv|abstand', c)}
    sequences = []
    for i in range(width):
        if i in skip:
            continue
        values = []
        for row in rows:
            x = _number(row[i], decimal_comma) if i < len(row) else None
            if x is None:
                if values:
                    break          # an empty cell ends a column pasted beside a longer one
                continue
            values.append(x)
        if not values:
            continue
        label = labels[i] or f'column {i + 1}'
        sequences.append(ImpactTimes(np.array(values), height_from_label(labels[i]),
                                     f'{source}: {label}'))
    if not sequences:
        raise ValueError(f'{source} has no impact times: allowed one column of times (s) per '
                         'sequence, or a phyphox Acoustic Stopwatch export')
    return sequences


def read_impact_times(path):
    """Sequences of impact times from a CSV file or phyphox export (``.csv`` or ``.zip``)."""
    sequences = parse_impact_times(_read_text(path), source=str(path))
    file_height = height_from_label(str(path).rsplit('/', 1)[-1])
    if file_height is not None and len(sequences) == 1 and sequences[0].height is None:
        s = sequences[0]
        sequences = [ImpactTimes(s.times, file_height, s.name)]
    return sequences
