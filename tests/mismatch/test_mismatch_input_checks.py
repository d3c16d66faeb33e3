"""Clear refusals and warnings of mismatch's inputs: a field for a series preset, a CSV without a
header, an input column with a hole, two wander classes, a loss term with the sign of a gain."""
import numpy as np

from odnn_sep.cli import main


def test_field_given_to_a_time_series_preset_is_refused(tmp_path, capsys):
    x, y = np.linspace(0, 1, 20), np.linspace(0, 1, 30)
    X, Y = np.meshgrid(x, y)
    f = tmp_path / "f.npz"
    np.savez(f, x=x, y=y, z=np.sin(3 * X) * Y)
    for model in ("oscillator", "cooling", "freefall"):
        assert main(["mismatch", str(f), "--model", model]) != 0
        err = capsys.readouterr().err
        assert "2-D field" in err and "Traceback" not in err


def test_csv_without_header_is_refused(tmp_path, capsys):
    f = tmp_path / "nh.csv"
    np.savetxt(f, np.column_stack([np.arange(50.0), np.exp(-np.arange(50.0) / 20)]), delimiter=",")
    assert main(["mismatch", str(f), "--model", "cooling"]) != 0
    assert "no header row" in capsys.readouterr().err
    assert main(["separate", str(f), "--basis", "x", "-o", str(tmp_path / "o.csv")]) != 0
    assert "no header row" in capsys.readouterr().err
    assert not (tmp_path / "o.csv").exists()


def test_negative_radiation_is_warned():
    from odnn_sep.mismatch.inputs import physical_warnings

    assert any("heat gain" in w for w in physical_warnings({"r_rad": -0.02, "h": 0.01}))
    assert physical_warnings({"r_rad": 0.02, "h": 0.01}) == []


def test_input_column_with_an_empty_cell_names_the_line(tmp_path, capsys):
    t = np.linspace(0, 10, 50)
    rows = ["t,x,u"] + [f"{a},{np.cos(a)},{np.sin(a)}" for a in t]
    rows[7] = f"{t[6]},{np.cos(t[6])},"
    f = tmp_path / "in.csv"
    f.write_text("\n".join(rows) + "\n")
    assert main(["mismatch", str(f), "--model", "oscillator", "--input", "u"]) != 0
    assert "line 8" in capsys.readouterr().err


def test_two_wander_classes_are_refused(capsys):
    from odnn_sep.errors import InputError
    from odnn_sep.mismatch.disturbances import parse_disturbance

    try:
        parse_disturbance("slow,none")
    except InputError as e:
        assert "two wander classes" in str(e)
    else:
        raise AssertionError("slow,none accepted")
