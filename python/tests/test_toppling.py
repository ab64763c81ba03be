"""Rigid blocks from Python with a quantity of one's own: examples/python/toppling.py gives the
C++ driver examples/toppling --quick's regions.csv and critical friction to the bit, and the
row's critical friction lies within 5 % of Goodman and Bray's limit equilibrium.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_toppling.py
"""
import json
import os
import pathlib
import subprocess
import sys

import pytest

import tessera

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"


@pytest.fixture(scope="module")
def python_toppling(tmp_path_factory):
    out = tmp_path_factory.mktemp("py_toppling")
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(tessera.__file__).resolve().parents[1]))
    r = subprocess.run([sys.executable, str(EXAMPLES / "toppling.py"), "--quick", "--out", str(out)], env=env,
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout + r.stderr
    return out


def test_python_toppling_gives_the_cpp_drivers_bits(python_toppling, tmp_path):
    program = os.environ.get("TESSERA_TOPPLING")
    if not program:
        pytest.skip("TESSERA_TOPPLING is not set (the CTest python_tests sets it)")
    cpp = subprocess.run([program, "--quick", "--threads", "1", "--out", str(tmp_path)], capture_output=True, text=True,
                         check=False)
    assert cpp.returncode == 0, cpp.stderr
    assert (python_toppling / "regions.csv").read_text() == (tmp_path / "regions.csv").read_text()
    py, c = (json.loads((d / "summary.json").read_text()) for d in (python_toppling, tmp_path))
    for key in ("critical_friction_deg", "critical_friction_bracket_deg", "reference_critical_friction_deg", "steps"):
        assert py[key] == c[key], key


def test_python_toppling_finds_the_limit_equilibrium_friction(python_toppling):
    s = json.loads((python_toppling / "summary.json").read_text())
    assert s["reference_critical_friction_deg"] == pytest.approx(34.026, abs=1e-3)  # Goodman and Bray, psi = 20 deg
    assert abs(s["error_rel"]) < 0.05  # --quick: 5 bisections, -3.5 %
    lo, hi = s["critical_friction_bracket_deg"]
    assert lo < s["critical_friction_deg"] < hi
    # the regions: 5 deg below psi the whole row slides (moves far), 5 deg above the critical it stands
    rows = (python_toppling / "regions.csv").read_text().splitlines()[1:]
    moved = [float(r.split(",")[2]) for r in rows]
    assert moved[0] > 0.002 and moved[-1] < 0.002


def test_a_quantity_of_ones_own_stops_the_run_and_refuses_a_bad_return():
    g = tessera.geometry
    tess = g.separate_blocks([g.convex_polyhedron.box([0, 0, -1], [1, 1, 0]), g.convex_polyhedron.box([0, 0, 0], [1, 1, 1])])
    joint = tessera.contact.detected_dry_joints(
        tessera.law.dry_joint(1e8, 1e8, tessera.law.friction_angle.from_degrees(30)), tolerance=1e-3)
    s = tessera.instances.rigid_dry_damped_solver(tess, g.zone_blocks(tess), tessera.blocks.rigid.params(2000), joint)
    s.fix_block(0)
    s.set_gravity([0, 0, -9.81])
    sink = tessera.quantity.of(lambda m: -m.block_displacement(1)[2], "sink of block 1 (m)")
    assert sink.describe() == "sink of block 1 (m)"
    r = s.run_until(tessera.stop.when_settled(sink, 1e-9, tessera.stop.over_steps(100)) | tessera.stop.after_steps(10**5))
    # a 1 m cube of 2000 kg/m^3 on a joint of k_n = 1e8 Pa/m over 1 m^2: sinks rho g h / k_n = 1.96e-4 m
    assert r.reason.startswith("settled") and -s.block_displacement(1)[2] == pytest.approx(2000 * 9.81 / 1e8, rel=0.02)
    bad = tessera.quantity.of(lambda m: "two", "bad")
    with pytest.raises(tessera.Error, match=r"quantity.of 'bad': returned 'two', not a number"):
        s.run_until(tessera.stop.when_beyond(bad, 1.0))
