"""Reading recorded impact times: phyphox exports as they come from the phone."""
import numpy as np
import pytest

from contact_sim.calibration import parse_impact_times, read_impact_times


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
    with pytest.raises(ValueError, match='is a spreadsheet workbook: allowed CSV'):
        read_impact_times(tmp_path / 'run.xlsx')
    with pytest.raises(ValueError, match='has no impact times'):
        parse_impact_times('"a";"b"\n')
