"""Deformable blocks on detected contacts (instances.deformable_dry_damped_solver and
deformable_dry_solver) from Python: an elastic block resting on a held elastic base carries its
weight through its detected sub-contacts (sum of their z forces = rho V g), at the interface; a
released block falls at g undamped and at (1 - gamma) g damped; the contact params must say
deformable_blocks, and the refusal names the value.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_deformable_detected.py
"""
import numpy as np
import pytest

import tessera
from tessera import geometry, law, quantity, stop

E, NU, RHO, G = 1e9, 0.2, 2000.0, 9.81   # Pa, -, kg/m^3, m/s^2


def scene(solver=tessera.instances.deformable_dry_damped_solver, deformable=True, lift=0.0):
    """A 1 x 1 x 1 m base under z = 0 and a 0.6 x 0.6 x 0.5 m block on it (or `lift` m above)."""
    tess = geometry.separate_blocks([geometry.convex_polyhedron.box([0, 0, -1], [1, 1, 0]),
                                     geometry.convex_polyhedron.box([0.2, 0.2, lift], [0.8, 0.8, 0.5 + lift])])
    joint = tessera.contact.detected_dry_joints(law.dry_joint(1e9, 1e9, law.friction_angle.from_degrees(30)),
                                                tolerance=1e-3)
    joint.deformable_blocks = deformable
    return solver(tess, geometry.zone_blocks(tess), tessera.zones.linear_elastic_tet.params(E, NU, RHO), joint)


def test_a_resting_deformable_block_carries_its_weight_through_its_sub_contacts():
    s = scene()
    s.fix(s.gridpoints_on_plane(2, -1.0, 1e-9))  # the base's bottom
    s.set_gravity([0, 0, -G])
    top = s.gridpoints_of_block(1)
    r = s.run_until(stop.when_settled(quantity.mean_displacement(top, 2), 1e-13, stop.over_steps(2000))
                    | stop.after_steps(1_000_000))
    assert not r.hit_max_steps
    cs = s.contact_state()
    assert cs.size() == s.contact_count() >= 4
    assert (cs.block_a == 0).all() and (cs.block_b == 1).all()
    weight = RHO * 0.6 * 0.6 * 0.5 * G  # N
    # block 1 (B) is pushed up by the base: the sum of the z forces on B's side is its weight
    assert np.sum(cs.force[:, 2]) == pytest.approx(weight, rel=1e-6)
    # the same through the law's stresses
    assert np.abs(np.sum(cs.field("sigma_n_Pa") * cs.area)) == pytest.approx(weight, rel=1e-6)
    # friction holds the Poisson spread of the block and the base apart: shear forces that cancel
    assert np.abs(np.sum(cs.force[:, :2], axis=0)).max() < 1e-6 * weight
    # the sub-contacts sit on the interface at the block's bottom corners (its sinking and its
    # Poisson spread are microns)
    assert np.allclose(cs.position[:, 2], 0.0, atol=1e-4)
    assert np.all((cs.position[:, :2] >= 0.2 - 1e-5) & (cs.position[:, :2] <= 0.8 + 1e-5))
    # the fixed base bottom carries both blocks' weight
    base = s.gridpoints_on_plane(2, -1.0, 1e-9)
    both = RHO * (1.0 + 0.18) * G
    assert tessera.recorders.reaction_sum(s.gridpoints(), base)[2] == pytest.approx(both, rel=1e-6)


@pytest.mark.parametrize("damped", [False, True])
def test_a_block_falls_at_g_undamped_and_at_one_fifth_of_g_damped(damped):
    """The block 2 cm above the base, released (no contact within the 1 mm tolerance): the undamped
    solver lets it fall freely, v = -g t to round-off; local damping (gamma 0.8) opposes the
    unbalanced force, so the damped one lets it fall at (1 - gamma) g, within 2 % over 1000 steps
    (the first steps, before the velocity has a sign, take the full g: measured +0.8 %)."""
    solver = tessera.instances.deformable_dry_damped_solver if damped else tessera.instances.deformable_dry_solver
    s = scene(solver, lift=0.02)
    s.fix(s.gridpoints_on_plane(2, -1.0, 1e-9))
    s.set_gravity([0, 0, -G])
    s.run_until(stop.after_steps(1000 if damped else 200))
    assert s.contact_count() == 0
    v = s.gridpoints().velocity[s.gridpoints_of_block(1).nodes, 2]
    if damped:
        assert np.allclose(v, -(1 - 0.8) * G * s.time(), rtol=0.02, atol=0)
    else:
        assert np.allclose(v, -G * s.time(), rtol=1e-12, atol=0)


def test_rigid_contact_params_on_deformable_blocks_are_refused_naming_the_value():
    with pytest.raises(tessera.Error, match=r"deformable_blocks = 0 does not match the block model \(deformable\)"):
        scene(deformable=False)
