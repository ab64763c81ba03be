"""The step checker on a sound undamped run: a 1 m cube dropped (at rest, in touch) on a held base
through a dry joint of k_n = 1e9 Pa/m swings between its start and about twice its static
settlement u_s = m g / (k_n A), with no damping to stop it. Every swing brings it back near its
start, where gravity's work is near zero while its half-step kinetic energy is not; the checker
bounds the kinetic energy by the largest work so far (energy_balance.peak_work), so the run goes on.
Before that bound the checker stopped this run at step 2 000.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_step_checker.py
"""
import pytest

import tessera
from tessera import geometry, law, stop

RHO, G, K_N = 2400.0, 16.67, 1e9   # kg/m^3, m/s^2, Pa/m (a 1 m^2 face: K = 1e9 N/m)


def test_an_undamped_cube_dropped_on_a_stiff_joint_swings_without_being_stopped():
    tess = geometry.separate_blocks([geometry.convex_polyhedron.box([0, 0, -1], [1, 1, 0]),
                                     geometry.convex_polyhedron.box([0, 0, 0], [1, 1, 1])])
    joint = law.dry_joint(K_N, K_N, law.friction_angle.from_degrees(30))
    s = tessera.instances.rigid_dry_solver(tess, geometry.zone_blocks(tess), tessera.blocks.rigid.params(RHO),
                                           tessera.contact.detected_dry_joints(joint, tolerance=1e-3))
    s.fix_block(0)
    s.set_gravity([0, 0, -G])
    u_s = RHO * G / K_N  # m: the static settlement, 4.0e-5
    lowest, highest = 0.0, -1.0
    for _ in range(200):
        s.run_until(stop.after_steps(100))  # raises tessera.Error if the checker stops the run
        uz = s.block_displacement(1)[2]
        lowest, highest = min(lowest, uz), max(highest, uz)
    assert s.step_count() == 20_000
    # The swing: down to about 2 u_s (a step load on a spring; the leapfrog's overshoot is small at
    # this block's step), back up near its start.
    assert -2.3 * u_s <= lowest <= -1.9 * u_s
    assert highest >= -0.2 * u_s
    e = s.energies()
    assert e.damping_dissipated == 0.0
    assert e.peak_work >= 1.9 * RHO * G * u_s  # the most gravity gave: m g (2 u_s)

    # A symmetric drop turns nothing: the rotations stay at round-off, and the arrays hold the
    # per-block values row for row.
    rot, disp = s.block_rotations(), s.block_displacements()
    assert rot.shape == disp.shape == (2, 3)
    for b in range(2):
        assert (rot[b] == s.block_rotation(b)).all() and (disp[b] == s.block_displacement(b)).all()
    assert abs(rot).max() < 1e-9
    assert disp[1][2] == s.block_displacement(1)[2] != 0.0
