"""The Python module against C++: the README's arch driven from Python gives the C++ program's
bits (tessera._arch_reference runs tests/consumer/arch.cpp's scene with the stop conditions
written as C++ templates), and refusals arrive as tessera.Error naming the bad value.

    PYTHONPATH=build/release/python python3 -m pytest python/tests
"""
import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import tessera

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"
sys.path.insert(0, str(EXAMPLES))
import arch  # noqa: E402  (examples/python/arch.py)


def run_example(cwd):
    """Runs examples/python/arch.py in cwd with the package imported here (PYTHONPATH may be relative)."""
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(tessera.__file__).resolve().parents[1]))
    return subprocess.run([sys.executable, str(EXAMPLES / "arch.py")], cwd=cwd, env=env, capture_output=True,
                          text=True, check=False)


@pytest.fixture(scope="module")
def python_arch():
    return arch.run_arch()


@pytest.fixture(scope="module")
def cpp_arch():
    return tessera._arch_reference()


def test_arch_gives_the_cpp_bits(python_arch, cpp_arch):
    s, r, weight, crown = python_arch
    base = tessera.recorders.reaction_sum(s.gridpoints(), s.gridpoints_of_block(0))[2]
    # the same step count, step, reason and results, compared exactly (==, not approx)
    assert r.steps == cpp_arch["steps"]
    assert r.hit_max_steps == cpp_arch["hit_max_steps"]
    assert r.reason == cpp_arch["reason"]
    assert s.dt() == cpp_arch["dt"]
    assert s.time() == cpp_arch["time"]
    assert base == cpp_arch["base"]
    assert weight == cpp_arch["weight"]
    assert -s.block_displacement(crown)[2] == cpp_arch["sag"]


def test_arch_gives_the_cpp_programs_summary_and_curve_bits(tmp_path):
    """Runs tests/consumer/arch.cpp (TESSERA_ARCH_CPP, built by CMake) and examples/python/arch.py
    in two folders: the same summary text and the same arch.csv, byte for byte (17 digits: bits)."""
    program = os.environ.get("TESSERA_ARCH_CPP")
    if not program:
        pytest.skip("TESSERA_ARCH_CPP is not set (the CTest python_tests sets it)")
    (tmp_path / "cpp").mkdir()
    (tmp_path / "py").mkdir()
    cpp = subprocess.run([program], cwd=tmp_path / "cpp", capture_output=True, text=True, check=False)
    py = run_example(tmp_path / "py")
    assert cpp.returncode == 0 and py.returncode == 0, cpp.stderr + py.stderr
    assert py.stdout == cpp.stdout
    cpp_csv = (tmp_path / "cpp" / "arch.csv").read_text()
    assert cpp_csv.count("\n") > 20
    assert (tmp_path / "py" / "arch.csv").read_text() == cpp_csv


def test_arch_stands(python_arch):
    s, r, weight, crown = python_arch
    assert r.reason.startswith("settled")
    assert not r.hit_max_steps
    assert s.step_count() == r.steps > 1000
    # 21 blocks: a 6 x 1 x 0.5 m slab and 20 voussoirs of (2.4^2 - 2^2)/2 sin(pi/20) m^3, 2400 kg/m^3
    volume = 3.0 + 20 * (2.4**2 - 2.0**2) / 2 * math.sin(math.pi / 20) * 1.0
    assert weight == pytest.approx(2400 * 9.81 * volume, rel=1e-9)
    base = tessera.recorders.reaction_sum(s.gridpoints(), s.gridpoints_of_block(0))
    assert base[2] == pytest.approx(weight, rel=1e-3)
    assert abs(base[0]) < 1e-3 * weight and abs(base[1]) < 1e-3 * weight
    assert 0 < -s.block_displacement(crown)[2] < 1e-3


def test_state_arrives_as_read_only_numpy_views(python_arch):
    s, r, weight, crown = python_arch
    g = s.gridpoints()
    reaction = g.reaction
    assert isinstance(reaction, np.ndarray) and reaction.shape == (g.size(), 3)
    assert not reaction.flags.writeable
    with pytest.raises(ValueError):
        reaction[0, 0] = 1.0
    # the view is the solver's array: the base block's gridpoints carry the reaction sum
    base = s.gridpoints_of_block(0)
    assert reaction[base.nodes].sum(axis=0)[2] == pytest.approx(
        tessera.recorders.reaction_sum(g, base)[2], rel=1e-12)
    u = s.block_displacement(crown)
    assert isinstance(u, np.ndarray) and u.shape == (3,)


def test_example_prints_the_summary_and_passes(tmp_path):
    out = run_example(tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
    assert " steps of " in out.stdout and ": settled: z displacement of block 10 (m)" in out.stdout
    assert "base reaction" in out.stdout and "crown sag" in out.stdout
    assert (tmp_path / "arch.csv").read_text().startswith("step,time_s,uz_crown_m,Rz_base_N\n0,0,0,0\n200,")


def test_negative_friction_angle_is_refused_naming_it():
    with pytest.raises(tessera.Error, match=r"friction angle = -5 deg must be in \[0, 90\)"):
        tessera.law.dry_joint(1e10, 1e10, tessera.law.friction_angle.from_degrees(-5))


def test_non_positive_stiffness_is_refused_naming_it():
    phi = tessera.law.friction_angle.from_degrees(30)
    with pytest.raises(tessera.InvalidInput, match=r"normal stiffness k_n = -1 Pa/m must be finite and > 0"):
        tessera.law.dry_joint(-1.0, 1e10, phi)
    with pytest.raises(tessera.Error, match=r"shear stiffness k_s = 0 Pa/m"):
        tessera.law.dry_joint(1e10, 0.0, phi)


def test_nan_gravity_and_bad_stop_values_are_refused_naming_them(python_arch):
    s = python_arch[0]
    with pytest.raises(tessera.Error, match=r"gravity \(.*nan.*\) m/s\^2 is not finite"):
        s.set_gravity([0.0, float("nan"), -9.81])
    with pytest.raises(tessera.Error, match=r"t = -1 s must be finite and >= 0"):
        tessera.stop.after_time(-1.0)
    with pytest.raises(tessera.Error, match=r"block -3 does not exist"):
        tessera.quantity.block_displacement(-3, 2)


def test_geometry_refusal_is_a_tessera_error():
    with pytest.raises(tessera.Error, match=r"inner radius r_in = 2.5 m must be < outer radius r_out = 2.4 m"):
        tessera.geometry.voussoir([0, 0, 0], 2.5, 2.4, 0.0, 0.1, 1.0)


def test_stop_conditions_compose_and_describe():
    c = tessera.stop.after_steps(5) | tessera.stop.after_time(1.0)
    assert c.describe() == "(after 5 steps) or (after 1 s)"
    d = tessera.stop.after_steps(5) & tessera.stop.kinetic_energy_below(0.5)
    assert d.describe() == "(after 5 steps) and (kinetic energy below 0.5 of its peak)"


def small_arch(solver="rigid_dry_damped_solver"):
    """The arch's geometry and joints with the given solver of tessera.instances, base held, gravity on."""
    g = tessera.geometry
    n = 20
    blocks = [g.convex_polyhedron.box([-3, -0.5, -0.5], [3, 0.5, 0])]
    blocks += [g.voussoir([0, 0, 0], 2.0, 2.4, math.pi * k / n, math.pi * (k + 1) / n, 1.0) for k in range(n)]
    tess = g.separate_blocks(blocks)
    joint = tessera.contact.detected_dry_joints(
        tessera.law.dry_joint(1e10, 1e10, tessera.law.friction_angle.from_degrees(35)), tolerance=1e-3)
    s = getattr(tessera.instances, solver)(tess, g.zone_blocks(tess), tessera.blocks.rigid.params(2400), joint)
    s.fix_blocks(s.blocks_below(2, 0.0))
    s.set_gravity([0, 0, -9.81])
    return s


def test_python_callable_stops_the_run_at_its_checks():
    s = small_arch()
    seen = []

    def past_250_steps(solver):
        seen.append(solver.step_count())
        return solver.step_count() >= 250

    r = s.run_until(tessera.stop.when(past_250_steps, "250 steps taken", every=100))
    # called before steps 0, 100, 200 and 300: the first check at or past 250 is at 300
    assert seen == [0, 100, 200, 300]
    assert r.steps == 300 and r.reason == "250 steps taken" and not r.hit_max_steps
    # every=1 stops where the C++ condition after_steps(250) does, on a second solver built alike
    t = small_arch()
    r1 = t.run_until(tessera.stop.when(lambda solver: solver.step_count() >= 250, "250 steps", every=1))
    u = small_arch()
    r2 = u.run_until(tessera.stop.after_steps(250))
    assert r1.steps == r2.steps == 250
    assert t.block_displacement(10)[2] == u.block_displacement(10)[2]


def test_ctrl_c_during_run_until_arrives_as_keyboard_interrupt():
    import _thread
    import threading

    s = small_arch()
    threading.Timer(0.5, _thread.interrupt_main).start()  # a trigger, not a timed assert
    with pytest.raises(KeyboardInterrupt):
        s.run_until(tessera.stop.after_steps(10**12), 10**12)
    assert 0 < s.step_count() < 10**12


def test_undamped_solver_keeps_moving_where_the_damped_one_settles():
    damped, undamped = small_arch(), small_arch("rigid_dry_solver")
    damped.run_until(tessera.stop.after_time(0.1))
    undamped.run_until(tessera.stop.after_time(0.1))
    assert damped.time() >= 0.1 and undamped.time() >= 0.1
    # without local damping the arch still rings after 0.1 s: far more kinetic energy left
    assert undamped.kinetic_energy() > 10 * damped.kinetic_energy()


def test_bad_callable_every_is_refused():
    with pytest.raises(tessera.Error, match=r"every = 0 steps must be >= 1"):
        tessera.stop.when(lambda s: True, "never", every=0)


def test_an_exception_in_the_callable_ends_the_run_and_the_solver_runs_on():
    s = small_arch()

    def fails_at_step_100(solver):
        if solver.step_count() == 100:
            raise ZeroDivisionError("from the callable at step %d" % solver.step_count())
        return False

    with pytest.raises(ZeroDivisionError, match="from the callable at step 100"):
        s.run_until(tessera.stop.after_steps(10**6) | tessera.stop.when(fails_at_step_100, "fails", every=1))
    assert s.step_count() == 100
    r = s.run_until(tessera.stop.after_steps(10))
    assert r.steps == 10 and s.step_count() == 110 and r.reason == "after 10 steps (limit 10)"


def test_csv_recorder_writes_the_cpp_recorders_file(tmp_path):
    """s.csv_recorder with the C++ program's columns and sampling (tests/consumer/arch.cpp:
    recorders::csv_recorder every 200 steps) writes its arch.csv byte for byte."""
    program = os.environ.get("TESSERA_ARCH_CPP")
    if not program:
        pytest.skip("TESSERA_ARCH_CPP is not set (the CTest python_tests sets it)")
    subprocess.run([program], cwd=tmp_path, capture_output=True, check=True)
    s = small_arch()
    q = tessera.quantity
    with s.csv_recorder(str(tmp_path / "py.csv"), [("uz_crown", "m", q.block_displacement(10, 2)),
                                                   ("Rz_base", "N", q.reaction_sum(s.gridpoints_of_block(0), 2))],
                        every_steps=200) as rec:
        until = (tessera.stop.when_settled(q.block_displacement(10, 2), 1e-8, tessera.stop.over_time(0.05))
                 | tessera.stop.when_beyond(q.block_displacement_magnitude(10), 0.05) | tessera.stop.after_time(3.0))
        s.run_until(until, 100_000_000, record=[rec])
        assert not (tmp_path / "py.csv").exists()  # the rows go to a temporary file until close
    assert rec.rows() > 20
    assert (tmp_path / "py.csv").read_text() == (tmp_path / "arch.csv").read_text()


def test_csv_recorder_refuses_bad_columns_naming_them(tmp_path):
    s = small_arch()
    q = tessera.quantity.time()
    with pytest.raises(tessera.Error, match=r"column 'a,b' contains a comma"):
        s.csv_recorder(str(tmp_path / "x.csv"), [("a,b", "m", q)], every_steps=10)
    with pytest.raises(tessera.Error, match=r"give one of every_steps = 0 \(>= 1\) and every_seconds = 0 s"):
        s.csv_recorder(str(tmp_path / "x.csv"), [("t", "s", q)])
    with pytest.raises(tessera.Error, match=r"column 't_s' is named twice"):
        s.csv_recorder(str(tmp_path / "x.csv"), [("t", "s", q), ("t", "s", q)], every_steps=1)
    assert not (tmp_path / "x.csv").exists()
