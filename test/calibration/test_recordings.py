"""Reading recorded impact times: phyphox exports as they come from the phone."""
import numpy as np
import pytest

from contact_sim.calibration import height_from_label, parse_impact_times, read_impact_times


def test_phyphox_exports_read_as_they_are(tmp_path):
    # the All sheet, semicolon and decimal comma, two runs pasted side by side, empty cells
    text = ('"Event time (s) h=80cm";"Interval (s)";"Event time (s) 50 cm";"Interval (s)"\n'
            '1,250000;0,600000;0,5;0,4\n1,850000;0,500000;0,9;0,3\n2,350000;;1,2;\n'
            '2,760000;;;\n')
    a, b = parse_impact_times(text)
    assert np.allclose(a.times, [1.25, 1.85, 2.35, 2.76]) and a.height == pytest.approx(0.8)
    assert np.allclose(b.times, [0.5, 0.9, 1.2]) and b.height == pytest.approx(0.5)
    # comma separated with a decimal point, no header
    (c,) = parse_impact_times('0.1\n0.7\n1.2 # a comment\n')
    assert np.allclose(c.times, [0.1, 0.7, 1.2]) and c.height is None
    # tab separated Multiple sheet: a run of six events per row
    (d,) = parse_impact_times('"Start (s)"\t"Stop 1 (s)"\t"Stop 2 (s)"\t"Stop 3 (s)"\n'
                              '0,1\t0,7\t1,2\t1,6\n')
    assert np.allclose(d.times, [0.1, 0.7, 1.2, 1.6])
    # the zip of the CSV export: its All file; the height from the file name
    import zipfile
    path = tmp_path / 'tennis_ball_120cm.zip'
    with zipfile.ZipFile(path, 'w') as z:
        z.writestr('Simple.csv', '"Start (s)","Stop (s)","Difference (s)"\n1,2,1\n')
        z.writestr('All.csv', '"Event time (s)","Interval (s)"\n1.0,0.5\n1.5,0.4\n1.9,\n')
    (e,) = read_impact_times(path)
    assert np.allclose(e.times, [1.0, 1.5, 1.9])
    assert e.height == pytest.approx(1.2)
    # sheet files named otherwise: the one holding every event
    other = tmp_path / 'run.zip'
    with zipfile.ZipFile(other, 'w') as z:
        z.writestr('Einfach.csv', '"Start (s)";"Stopp (s)"\n1;2\n')
        z.writestr('Alle Ereignisse.csv', '"Zeit (s)";"Intervall (s)"\n1,0;0,5\n1,5;0,4\n'
                                          '1,9;\n2,2;\n')
    (f,) = read_impact_times(other)
    assert np.allclose(f.times, [1.0, 1.5, 1.9, 2.2])
    with pytest.raises(ValueError, match='is an OpenDocument workbook: allowed CSV, .xlsx or'):
        read_impact_times(tmp_path / 'run.ods')
    with pytest.raises(ValueError, match='has no impact times'):
        parse_impact_times('"a";"b"\n')


def test_heights_in_names_with_decimal_commas_and_units():
    # found: height_from_label('Lancio1,10cm.csv') gave 0.011 m, silently
    from contact_sim.calibration.recordings import heights_from_label
    assert height_from_label('Lancio1,10cm.csv') == pytest.approx(0.10)
    assert height_from_label('drop_1,5m.csv') == pytest.approx(1.5)
    assert height_from_label('ball 250mm') == pytest.approx(0.25)
    assert height_from_label('h=0,8') == pytest.approx(0.8)
    assert height_from_label('run3.csv') is None
    assert heights_from_label('golf_80cm_1,2m.csv') == pytest.approx([0.8, 1.2])


def test_runs_side_by_side_take_the_heights_in_the_file_name(tmp_path):
    # found: a file of several runs ignored the height in its name (20 --height flags needed)
    runs = '"Event time (s)","Event time (s)"\n0.0,0.0\n0.6,0.5\n1.1,0.9\n'
    one = tmp_path / 'Lancio1,10cm.csv'
    one.write_text(runs)
    assert [s.height for s in read_impact_times(one)] == pytest.approx([0.1, 0.1])
    each = tmp_path / 'golf_80cm_1m.csv'
    each.write_text(runs)
    assert [s.height for s in read_impact_times(each)] == pytest.approx([0.8, 1.0])
    three = tmp_path / 'golf_80cm_1m_2m.csv'
    three.write_text(runs)
    with pytest.raises(ValueError, match='names 3 heights for 2 runs'):
        read_impact_times(three)


def test_an_event_index_column_is_not_a_sequence_of_times():
    # found: `event_index,event_time_s` fitted event_index as times, exit 0
    text = 'event_index,event_time_s\n0,0.25\n1,0.85\n2,1.35\n3,1.76\n'
    (seq,) = parse_impact_times(text)
    assert np.allclose(seq.times, [0.25, 0.85, 1.35, 1.76])
    (unnamed,) = parse_impact_times('1,0.25\n2,0.85\n3,1.35\n')
    assert np.allclose(unnamed.times, [0.25, 0.85, 1.35])


def test_column_selection_by_header_or_number():
    text = 'a,b,c\n0.1,0.2,0.3\n0.7,0.9,0.8\n1.2,1.5,1.2\n'
    assert [s.name for s in parse_impact_times(text, columns=['B', '3'])] == \
        ['data: b', 'data: c']
    with pytest.raises(ValueError, match=r"column = 'x' is not in data: allowed a header "
                                         r"\('a', 'b', 'c'\) or a number 1 to 3"):
        parse_impact_times(text, columns=['x'])


def test_a_last_event_kept_only_as_an_interval_is_read():
    # found: the interval column was ignored, and with it a sheet's last event
    text = '"Event time (s)";"Interval (s)"\n1,0;0,5\n1,5;0,4\n1,9;0,3\n'
    (seq,) = parse_impact_times(text)
    assert np.allclose(seq.times, [1.0, 1.5, 1.9, 2.2])


def test_messages_carry_plain_numbers():
    # found: `times[1] = np.float64(110.0) is out of range`
    with pytest.raises(ValueError) as error:
        parse_impact_times('t\n120\n110\n130\n')
    assert 'times[1] = 110.0 is out of range' in str(error.value)
    assert 'np.' not in str(error.value)


PHYPHOX_SHEETS = {
    'Simple': [['Start (s)', 'Stop (s)', 'Difference (s)'], [1.0, 1.5, 0.5]],
    'Multiple': [['Start (s)', 'Stop 1 (s)', 'Stop 2 (s)'], [1.0, 1.5, 1.9]],
    'All': [['Event time (s)', 'Interval (s)'], [1.0, 0.5], [1.5, 0.4], [1.9, 0.33],
            [2.23, 0.28]],              # the last event kept only as an interval: 2.51 s
    'Metadata Device': [['property', 'value'], ['model', 'phone']],
}
PHYPHOX_ALL = [1.0, 1.5, 1.9, 2.23, 2.51]


def test_a_phyphox_xlsx_workbook_is_read_directly(tmp_path):
    # found: .xls/.xlsx were refused ("allowed CSV")
    import openpyxl
    book = openpyxl.Workbook()
    book.remove(book.active)
    for name, rows in PHYPHOX_SHEETS.items():
        sheet = book.create_sheet(name)
        for row in rows:
            sheet.append(row)
    path = tmp_path / 'Lancio2,80cm.xlsx'
    book.save(path)
    (seq,) = read_impact_times(path)
    assert np.allclose(seq.times, PHYPHOX_ALL)
    assert seq.height == pytest.approx(0.8)


def test_a_phyphox_xls_workbook_is_read_directly(tmp_path):
    import xlwt
    book = xlwt.Workbook()
    for name, rows in PHYPHOX_SHEETS.items():
        sheet = book.add_sheet(name)
        for i, row in enumerate(rows):
            for j, cell in enumerate(row):
                sheet.write(i, j, cell)
    path = tmp_path / 'golf 1m.xls'
    book.save(str(path))
    (seq,) = read_impact_times(path)
    assert np.allclose(seq.times, PHYPHOX_ALL)
    assert seq.height == pytest.approx(1.0)
    bad = tmp_path / 'broken.xlsx'
    bad.write_bytes(b'not a zip')
    with pytest.raises(ValueError, match="data = '.*broken.xlsx' cannot be read as a workbook"):
        read_impact_times(bad)


def test_a_long_table_is_grouped_by_its_trial_column(tmp_path):
    # found: no grouping of a long table by its trial column
    path = tmp_path / 'trials.csv'
    path.write_text('trial;event;time (s)\n'
                    'drop 80cm;1;0,40\ndrop 80cm;2;1,10\ndrop 80cm;3;1,70\n'
                    'drop 1m;1;0,45\ndrop 1m;2;1,25\ndrop 1m;3;1,93\ndrop 1m;4;2,50\n')
    first, second = read_impact_times(path, group_by='trial')
    assert np.allclose(first.times, [0.40, 1.10, 1.70]) and first.height == pytest.approx(0.8)
    assert np.allclose(second.times, [0.45, 1.25, 1.93, 2.50])
    assert second.height == pytest.approx(1.0)
    assert second.name.endswith('trial = drop 1m')
    with pytest.raises(ValueError, match="column = 'run' is not in"):
        read_impact_times(path, group_by='run')
