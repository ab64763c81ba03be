"""The Brazilian disc from Python: examples/python/brazilian.py --quick gives the C++ driver
examples/brazilian --quick --threads 1's curve.csv byte for byte (the disc that splits, and one
stopped at 5 um before it does), the splitting strength lies in the driver's CTest band, and bad
disc values are refused naming them.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_brazilian.py
"""
import json
import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import tessera
from tessera import geometry

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"


def run_script(args, out):
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(tessera.__file__).resolve().parents[1]))
    r = subprocess.run([sys.executable, str(EXAMPLES / "brazilian.py"), "--quick", "--out", str(out)] + args, env=env,
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def run_driver(args, out):
    program = os.environ.get("TESSERA_BRAZILIAN")
    if not program:
        pytest.skip("TESSERA_BRAZILIAN is not set (the CTest python_tests sets it)")
    cpp = subprocess.run([program, "--quick", "--threads", "1", "--out", str(out)] + args, capture_output=True,
                         text=True, check=False)
    assert cpp.returncode == 0, cpp.stdout + cpp.stderr
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def python_disc(tmp_path_factory):
    out = tmp_path_factory.mktemp("py_brazilian")
    return out, run_script([], out)


def test_python_disc_gives_the_cpp_drivers_curve_bits(python_disc, tmp_path):
    """brazilian --quick --threads 1 (the CTest example_brazilian_quick) and the script: the same
    curve.csv byte for byte (17 digits: bits), the same peak, split and step count."""
    c = run_driver([], tmp_path)
    cpp_csv = (tmp_path / "curve.csv").read_text()
    assert cpp_csv.count("\n") > 100  # a row every 0.2 um to 1.2 x the split displacement
    assert (python_disc[0] / "curve.csv").read_text() == cpp_csv
    py = json.loads((python_disc[0] / "summary.json").read_text())
    for key in ("blocks", "steps", "split", "split_by_hinge", "peak_load_N", "split_displacement_m", "f_sp_Pa", "f_T_Pa",
                "bottom_over_top_at_peak_rel", "energy_balance_error_rel", "dt_s"):
        assert py[key] == c[key], key


def test_python_disc_stopped_before_the_split_gives_the_drivers_bits(tmp_path):
    """--max-displacement 5e-6 (the CTest example_brazilian_not_split): no split, no f_sp, the
    same curve.csv as the driver's."""
    run_script(["--max-displacement", "5e-6"], tmp_path / "py")
    c = run_driver(["--max-displacement", "5e-6"], tmp_path / "cpp")
    assert c["split"] is False
    py = json.loads((tmp_path / "py" / "summary.json").read_text())
    assert py["split"] is False and py["f_sp_Pa"] is None and py["largest_load_N"] == c["largest_load_N"] > 1000
    assert (tmp_path / "py" / "curve.csv").read_text() == (tmp_path / "cpp" / "curve.csv").read_text()


def test_python_disc_splits_within_the_drivers_band(python_disc):
    out, stdout = python_disc
    s = json.loads((out / "summary.json").read_text())
    assert s["blocks"] == 38  # the 100-block prism's mean block volume in the 36-gon disc
    assert s["split"] is True and 1.8 < s["f_sp_over_f_T"] < 3.0  # the driver's CTest band (quick seed 1: 2.30)
    # f_sp = 2 P / (pi D t) with D = 150 mm, t = 60 mm
    assert s["f_sp_Pa"] == pytest.approx(2 * s["peak_load_N"] / (math.pi * 0.15 * 0.06), rel=1e-15)
    assert abs(s["bottom_over_top_at_peak_rel"]) < 0.05  # quasi-static at the peak
    assert abs(s["energy_balance_error_rel"]) < 1e-3
    curve = np.loadtxt(out / "curve.csv", delimiter=",", skiprows=1)
    u, p_top = curve[:, 0], curve[:, 1]
    # a row every 40 steps of 5 nm: u = 0.2 um x row number
    assert u[0] == pytest.approx(2e-7, rel=1e-9) and np.allclose(np.diff(u), 2e-7, rtol=1e-6)
    # the split ends the run at 1.2 x its displacement; the peak comes before it
    assert u[-1] == pytest.approx(1.2 * s["split_displacement_m"], abs=2e-7)
    assert s["peak_displacement_m"] <= s["split_displacement_m"] and p_top.max() >= s["peak_load_N"]
    assert "f_sp" in stdout


def test_disc_geometry_has_its_closed_form_volume_and_bad_values_are_refused():
    R, t, n = 0.075, 0.06, 36
    disc = geometry.cylinder_prism([0, 0, 0], [0, 0, 1], R, t, n, math.pi / n)
    assert disc.volume() == pytest.approx(0.5 * n * R * R * math.sin(2 * math.pi / n) * t, rel=1e-12)
    assert np.allclose(disc.centroid(), 0, atol=1e-15)
    with pytest.raises(tessera.Error, match=r"sides = 2"):
        geometry.cylinder_prism([0, 0, 0], [0, 0, 1], R, t, 2)
    with pytest.raises(tessera.Error, match=r"-0.075"):
        geometry.cylinder_prism([0, 0, 0], [0, 0, 1], -R, t, n)
    with pytest.raises(tessera.Error, match=r"number of cells N = 0"):
        geometry.random_voronoi(disc, 0, 1)
