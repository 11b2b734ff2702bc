"""The sheets of a workbook of impact times (``.xlsx`` by openpyxl, ``.xls`` by xlrd, both
imported only here), and which of them hold runs.

Every sheet is read, with a word for each one left out: an empty sheet, a metadata sheet, and in
a phyphox export the ``Simple`` and ``Multiple`` sheets, which repeat the first events of its
``All`` sheet.  Runs on several sheets (a sheet per height, a sheet per ball) are all read.
Units: SI.
"""
import os
import re
import zipfile

from contact_sim.validation import InputError

MAX_BYTES = 64 * 2**20     # size of a file read for impact times
MAX_ROWS = 100_000         # rows of a workbook read for impact times (all sheets together)
_ALL = re.compile(r'\ball\b', re.IGNORECASE)
_REPEATS = re.compile(r'^\s*(simple|multiple)\s*$', re.IGNORECASE)
_METADATA = re.compile(r'meta\s*data', re.IGNORECASE)


def _cell(c):
    if c is None:
        return ''
    if isinstance(c, (int, float)) and not isinstance(c, bool):
        c = float(c)
        return str(int(c)) if c.is_integer() and abs(c) < 1e15 else repr(c)
    return str(c)


def workbook_sheets(path):
    """Every sheet of the workbook ``path`` as rows of cell texts, in the workbook's order.

    Parameters
    ----------
    path : str or Path
        A ``.xlsx`` or ``.xls`` file.

    Returns
    -------
    list of (str, list of list of str)
        (sheet name, rows).

    Raises
    ------
    InputError, ValueError
        If the file cannot be read as a workbook or holds more than ``MAX_ROWS`` rows.
    """
    name = str(path)
    try:
        if name.lower().endswith('.xlsx'):
            import openpyxl
            book = openpyxl.load_workbook(path, read_only=True, data_only=True)
            sheets = [(ws.title, [list(r) for r in ws.iter_rows(values_only=True)])
                      for ws in book.worksheets]
            book.close()
        else:
            import xlrd
            book = xlrd.open_workbook(path)
            sheets = [(sh.name, [sh.row_values(i) for i in range(sh.nrows)])
                      for sh in book.sheets()]
    except ImportError as error:
        raise ValueError(f'data = {name!r} is a workbook and {error.name} is not installed: '
                         'pip install openpyxl xlrd (or save the All sheet as CSV)') from None
    except MemoryError:
        raise InputError('data', name, '{n[data]} = {value} is too large to read as a '
                         'workbook: allowed at most %d rows' % MAX_ROWS) from None
    except Exception as error:      # each library has its own errors for a bad file
        raise ValueError(f'data = {name!r} cannot be read as a workbook: {error}') from None
    rows = sum(len(r) for _, r in sheets)
    if rows > MAX_ROWS:
        raise InputError('data', name, '{n[data]} = {value} has %d rows: allowed at most %d'
                         % (rows, MAX_ROWS))
    return [(title, [[_cell(c) for c in row] for row in r]) for title, r in sheets]


def sheets_to_read(sheets):
    """The sheets that may hold runs, and a word on each one left out.

    Parameters
    ----------
    sheets : list of (str, rows)
        ``workbook_sheets``' result.

    Returns
    -------
    (list of (str, rows), list of str)
        The sheets to read, and the reasons for the others (``'Sheet1 (empty)'``).

    Examples
    --------
    >>> from contact_sim.calibration.workbooks import sheets_to_read
    >>> book = [('Simple', [['Start (s)']]), ('All', [['Event time (s)'], ['0.5']]),
    ...         ('Metadata Time', [['event']]), ('Sheet1', [])]
    >>> read, left = sheets_to_read(book)
    >>> [name for name, _ in read], left
    (['All'], ["Simple (phyphox's repeat of the first events of All)", 'Metadata Time \
(metadata)', 'Sheet1 (empty)'])
    """
    has_all = [name for name, _ in sheets if _ALL.search(name)]
    read, left = [], []
    for name, rows in sheets:
        if not any(c.strip() for row in rows for c in row):
            left.append(f'{name} (empty)')
        elif _METADATA.search(name):
            left.append(f'{name} (metadata)')
        elif has_all and _REPEATS.match(name):
            left.append(f"{name} (phyphox's repeat of the first events of {has_all[0]})")
        else:
            read.append((name, rows))
    return read, left


def read_text(path):
    """The text of a CSV file, or of the ``All`` CSV (else the longest) of a zip of them."""
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
