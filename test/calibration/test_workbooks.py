"""Every workbook read whole (issue 32): runs on several sheets, side by side, stacked between
empty cells, a combined table grouped by several columns and filtered to one ball, with a word
for everything not read; and the reader's refusals (issue 34)."""
import math

import numpy as np
import pytest

from contact_sim import InputError
from contact_sim.calibration import (ImpactTimes, height_from_label, parse_impact_times,
                                     read_impact_times)
from contact_sim.calibration.workbooks import sheets_to_read


def drop(h, e=0.8, n=6, t0=0.3):
    """Vacuum click times of a drop from h metres."""
    v, t = e * math.sqrt(2 * 9.81 * h), [t0]
    for _ in range(n - 1):
        t.append(t[-1] + 2 * v / 9.81)
        v *= e
    return t


@pytest.fixture
def golf_book(tmp_path):
    """Golf runs as people save them: two sheets named by height with runs side by side (an
    event-number column beside them), a phyphox-like metadata sheet, an empty sheet, and a
    combined table of two balls."""
    import openpyxl
    book = openpyxl.Workbook()
    first = book.active
    first.title = '80cm'
    first.append(['run 1', 'run 2', 'n'])
    for i, (a, b) in enumerate(zip(drop(0.8), drop(0.8, t0=0.5))):
        first.append([a, b, i])
    second = book.create_sheet('50cm')
    second.append(['run 3', 'run 4', 'run 5'])
    for row in zip(drop(0.5), drop(0.5, t0=0.2), drop(0.5, t0=0.4)):
        second.append(list(row))
    book.create_sheet('Metadata Device').append(['property', 'value'])
    book.create_sheet('Sheet1')
    table = book.create_sheet('combined')
    table.append(['ball', 'height_cm', 'trial', 'time (s)'])
    for ball in ('golf', 'tt'):
        for h in (80, 50):
            for trial in (1, 2):
                for t in drop(h / 100, e=0.8 if ball == 'golf' else 0.9):
                    table.append([ball, h, trial, t])
    path = tmp_path / 'golf.xlsx'
    book.save(path)
    return path


def test_runs_on_every_sheet_are_read_and_the_rest_named(golf_book):
    # found: only the first sheet was read, 15 of 20 golf runs dropped without a word
    notes = []
    with pytest.raises(InputError, match=r'\[combined\]: time \(s\).*--group-by'):
        read_impact_times(golf_book, notes=notes)    # a combined table needs its trial columns
    notes = []
    runs = read_impact_times(golf_book, columns=['run 1', 'run 3'], notes=notes)
    assert [r.name.rsplit(' ', 1)[-1] for r in runs] == ['1', '3']
    # the sheet's name gives the runs their height
    assert [r.height for r in runs] == [pytest.approx(0.8), pytest.approx(0.5)]
    assert "column = 'run 1' is not in" in notes[0] and '[combined]' in notes[0]
    assert 'Metadata Device (metadata)' in notes[0] and 'Sheet1 (empty)' in notes[0]


def test_side_by_side_sheets_read_whole_with_the_event_numbers_named(tmp_path):
    import openpyxl
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.title = '80cm'
    sheet.append(['run 1', 'run 2', 'n'])
    for i, (a, b) in enumerate(zip(drop(0.8), drop(0.8, t0=0.5))):
        sheet.append([a, b, i])
    sheet.append([None, None, None])
    for t in drop(0.8, t0=9.0)[:4]:      # a third run stacked under the first, after a gap
        sheet.append([t])
    other = book.create_sheet('50cm')
    other.append(['run 3'])
    for t in drop(0.5):
        other.append([t])
    path = tmp_path / 'golf runs.xlsx'
    book.save(path)
    notes = []
    runs = read_impact_times(path, notes=notes)
    assert [r.times.size for r in runs] == [6, 4, 6, 6]
    assert np.allclose(runs[1].times, drop(0.8, t0=9.0)[:4])
    assert "'n' not read: it numbers the events" in ' '.join(notes)
    assert "'run 1' holds 2 blocks" in ' '.join(notes)
    assert notes[0].startswith(f'{path}: 4 run(s) read from sheet(s) \'80cm\', \'50cm\'')


def test_a_combined_table_grouped_by_several_columns_and_filtered_to_one_ball(golf_book):
    notes = []
    runs = read_impact_times(golf_book, group_by='ball,height_cm,trial',
                             where={'ball': 'GOLF'}, notes=notes)
    assert [r.name.split(': ', 1)[1] for r in runs] == [
        f'ball = golf, height_cm = {h}, trial = {t}' for h in (80, 50) for t in (1, 2)]
    # a number under a header with a unit is the run's height
    assert [r.height for r in runs] == pytest.approx([0.8, 0.8, 0.5, 0.5])
    assert np.allclose(runs[2].times, drop(0.5))
    assert '24 of 48 rows read (where ball=GOLF)' in ' '.join(notes)
    # numbers compare as numbers; a list of columns works as the comma-separated text
    runs = read_impact_times(golf_book, group_by=['ball', 'trial'],
                             where={'height_cm': '80.0'})
    assert len(runs) == 4 and all(r.times.size == 6 for r in runs)
    with pytest.raises(ValueError, match=r'where ball=steel matches no row .*golf, tt'):
        parse_impact_times('ball,t\ngolf,0\ngolf,1\ngolf,1.8\ntt,0\n', where={'ball': 'steel'})


def test_phyphox_repeats_are_not_read_twice():
    book = [('Simple', [['Start (s)', 'Stop (s)'], ['1', '2']]),
            ('All', [['Event time (s)'], ['1'], ['2'], ['2.8']])]
    read, left = sheets_to_read(book)
    assert [name for name, _ in read] == ['All'] and 'repeat' in left[0]
    # without an All sheet, a sheet named Simple is a sheet like any other
    assert [name for name, _ in sheets_to_read(book[:1])[0]] == ['Simple']


def test_reader_refusals_are_input_errors_naming_the_field(tmp_path):
    # found (issue 34): _csv.Error 'field larger than field limit', TypeError from
    # height_from_label, a number opened as a file descriptor
    big = tmp_path / 'big.csv'
    big.write_text('t\n' + 'x' * 2**20 + '\n0\n1\n1.8\n')
    with pytest.raises(InputError, match='has a line of 1048576 characters: allowed at most'):
        read_impact_times(big)
    with pytest.raises(InputError, match="data = 'data' has a line of 200002 characters"):
        parse_impact_times('t\n"' + 'x' * 200_001 + '\n0\n')
    with pytest.raises(InputError, match='name = 5 is not text'):
        ImpactTimes(np.array([0.0, 1.0, 1.8]), None, 5)
    for label in (5, None, b'80cm'):
        with pytest.raises(InputError, match='label = .* is not text'):
            height_from_label(label)
    with pytest.raises(InputError, match='data = 5 is not a file name'):
        read_impact_times(5)
    with pytest.raises(InputError, match='column = 5 is not a list'):
        parse_impact_times('a\n0\n1\n1.8\n', columns=5)
    with pytest.raises(InputError, match='group_by'):
        parse_impact_times('a,b\n0,1\n', group_by=' , ')


def test_notes_of_several_workbooks_come_in_the_order_they_are_read(golf_book, tmp_path):
    # found: `bounces a.xlsx b.xlsx c.xlsx` printed the '# read:' lines c, b, a (each
    # workbook's summary was inserted at the front of the shared list)
    import shutil
    second = tmp_path / 'second.xlsx'
    shutil.copy(golf_book, second)
    notes = []
    for path in (golf_book, second):
        read_impact_times(path, columns=['run 1'], notes=notes)
    summaries = [n for n in notes if 'run(s) read from sheet(s)' in n]
    assert [s.split(':')[0] for s in summaries] == [str(golf_book), str(second)]
    assert notes.index(summaries[0]) == 0
    assert all(notes.index(n) > notes.index(summaries[0]) for n in notes if str(second) in n)
