"""Per-sub-contact state of the rigid solvers as NumPy arrays: a block at rest on a held base
carries its weight through its sub-contacts (sum of sigma_n A = m g), at the interface, along
its normal, without shear; a falling block resumed from a checkpoint takes the same steps to the
bit; and a bad field name is refused naming it.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_rigid_state.py
"""
import numpy as np
import pytest

import tessera
from tessera import geometry, law, quantity, stop

RHO, G = 2000.0, 9.81


@pytest.fixture(scope="module")
def resting_block():
    tess = geometry.separate_blocks([geometry.convex_polyhedron.box([0, 0, -1], [1, 1, 0]),
                                     geometry.convex_polyhedron.box([0.2, 0.2, 0], [0.8, 0.8, 0.5])])
    joint = tessera.contact.detected_dry_joints(law.dry_joint(1e9, 1e9, law.friction_angle.from_degrees(30)),
                                                tolerance=1e-3)
    s = tessera.instances.rigid_dry_damped_solver(tess, geometry.zone_blocks(tess), tessera.blocks.rigid.params(RHO), joint)
    s.fix_block(0)
    s.set_gravity([0, 0, -G])
    r = s.run_until(stop.when_settled(quantity.block_displacement(1, 2), 1e-12, stop.over_steps(500))
                    | stop.after_steps(200_000))
    assert not r.hit_max_steps
    return s


def test_a_resting_block_carries_its_weight_through_its_sub_contacts(resting_block):
    s = resting_block
    cs = s.contact_state()
    n = s.contact_count()
    assert cs.size() == n >= 4  # the 0.6 x 0.6 m face on the base: its corners at least
    assert (np.minimum(cs.block_a, cs.block_b) == 0).all() and (np.maximum(cs.block_a, cs.block_b) == 1).all()
    weight = RHO * 0.6 * 0.6 * 0.5 * G  # N
    sigma_n = cs.field("sigma_n_Pa")
    assert np.abs(np.sum(sigma_n * cs.area)) == pytest.approx(weight, rel=1e-6)
    assert np.allclose(np.abs(cs.normal[:, 2]), 1.0, atol=1e-9)  # the interface's normal
    # the point midway between the base's top (held at z = 0) and the block's bottom, which sank
    # by the overlap sigma_n / k_n = rho h g / k_n = 9.81 um: z = -4.905 um
    overlap = RHO * 0.5 * G / 1e9
    assert np.allclose(cs.position[:, 2], -0.5 * overlap, rtol=1e-6, atol=0)
    assert np.all((cs.position[:, :2] >= 0.2 - 1e-6) & (cs.position[:, :2] <= 0.8 + 1e-6))  # under the block
    # a dry joint is broken in tension and slipped from the start (no strength, no cohesion):
    # status broken_tension | slipped, damage 1; at rest it carries no shear
    st = law.contact_status
    assert (cs.status == int(st.broken_tension | st.slipped)).all() and (cs.tensile_damage == 1).all()
    assert np.abs(cs.field("tau_Pa")).max() < 1e-6 * np.abs(sigma_n).max()


def test_a_missing_field_is_refused_naming_it(resting_block):
    with pytest.raises(tessera.Error, match=r"no field 'damage_Pa'"):
        resting_block.contact_state().field("damage_Pa")


def settling_block():
    """A block 1 mm above a held base (rigid, damped), falling: its sub-contacts (within the 2 mm
    tolerance) start open and close during the run."""
    tess = geometry.separate_blocks([geometry.convex_polyhedron.box([0, 0, -1], [1, 1, 0]),
                                     geometry.convex_polyhedron.box([0.2, 0.2, 1e-3], [0.8, 0.8, 0.5])])
    joint = tessera.contact.detected_dry_joints(law.dry_joint(1e9, 1e9, law.friction_angle.from_degrees(30)),
                                                tolerance=2e-3)
    s = tessera.instances.rigid_dry_damped_solver(tess, geometry.zone_blocks(tess), tessera.blocks.rigid.params(RHO), joint)
    s.fix_block(0)
    s.set_gravity([0, 0, -G])
    return s


def test_a_rigid_run_resumed_from_a_checkpoint_takes_the_same_steps_to_the_bit(tmp_path, resumed):
    a, b, info = resumed(settling_block, 400, str(tmp_path / "rigid.ckpt"), "falling")
    assert info.description == "falling"
    assert (a.step_count(), a.time()) == (b.step_count(), b.time())
    assert np.array_equal(a.block_displacement(1), b.block_displacement(1))
    assert np.array_equal(a.block_velocity(1), b.block_velocity(1))
    ca, cb = a.contact_state(), b.contact_state()
    assert ca.size() == cb.size() > 0 and np.array_equal(ca.field("sigma_n_Pa"), cb.field("sigma_n_Pa"))
    assert a.block_displacement(1)[2] < -1e-4  # it fell: the compared state is not the start
