"""2-D fields (.npz) as users save them.

- ``x``, ``y`` straight from ``np.meshgrid`` (2-D, either indexing) were refused with "len(y) x len(x) is
  (1500, 1500)";
- the parts CSV of a field was headed ``x0,x1,y,...``: its column ``y`` held the field's values z, next to
  the coordinate the same file calls ``y`` elsewhere;
- ``--disturbance convex|monotone|band|periodic`` on a field ended in the engine's "needs 1-D sample points
  x; got shape (1500, 2)".
"""
import numpy as np
import pytest

from odnn_sep.cli import main

XA, YA = np.linspace(-1, 1, 12), np.linspace(-2, 2, 9)


def _field(X, Y):
    return 2 * np.sin(3 * X) * np.cos(Y) + X**2 + Y**2


def _parts(path):
    a = np.genfromtxt(path, delimiter=",", names=True)
    return a[np.lexsort((a["x"], a["y"]))]


@pytest.mark.parametrize("indexing", ["xy", "ij"])
def test_meshgrid_coordinates_give_the_same_fit_as_axes(tmp_path, indexing):
    X, Y = np.meshgrid(XA, YA)
    np.savez(tmp_path / "axes.npz", x=XA, y=YA, z=_field(X, Y))
    Xm, Ym = np.meshgrid(XA, YA, indexing=indexing)
    np.savez(tmp_path / "mesh.npz", x=Xm, y=Ym, z=_field(Xm, Ym))
    for name in ("axes", "mesh"):
        assert main(["separate", str(tmp_path / f"{name}.npz"), "--basis", "sin(3*x)*cos(y)", "--disturbance", "even",
                     "--quiet", "-o", str(tmp_path / f"{name}.csv")]) == 0
    a, b = _parts(tmp_path / "axes.csv"), _parts(tmp_path / "mesh.csv")
    assert a.dtype.names == b.dtype.names == ("x", "y", "z", "physics", "disturbance", "residual")
    for k in a.dtype.names:
        np.testing.assert_allclose(a[k], b[k], atol=1e-9)
    np.testing.assert_allclose(a["z"], _field(a["x"], a["y"]), atol=1e-8)


def test_scattered_2d_coordinates_refused(tmp_path, capsys):
    rng = np.random.default_rng(0)
    np.savez(tmp_path / "s.npz", x=rng.normal(size=(9, 12)), y=rng.normal(size=(9, 12)), z=np.zeros((9, 12)))
    assert main(["separate", str(tmp_path / "s.npz"), "--basis", "x", "--quiet"]) == 1
    assert "are 2-D but not a grid" in capsys.readouterr().err


@pytest.mark.parametrize("spec", ["convex", "monotone", "band:0:1", "periodic:1"])
def test_one_dimensional_classes_on_a_field(tmp_path, capsys, spec):
    X, Y = np.meshgrid(XA, YA)
    np.savez(tmp_path / "f.npz", x=XA, y=YA, z=_field(X, Y))
    assert main(["separate", str(tmp_path / "f.npz"), "--basis", "sin(3*x)*cos(y)", "--disturbance", spec,
                 "--quiet"]) == 1
    err = capsys.readouterr().err.strip()
    assert err == (f"Error: --disturbance {spec!r} is for a 1-D signal (a CSV); a 2-D field (.npz) takes orthogonal "
                   "or even[:cx,cy]")
