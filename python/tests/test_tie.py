"""The tie with bars (instances.tie_solver) from Python: an elastic reinforced tie pulled by a
small elongation, held still, balances at its middle joint (the sub-contacts' force plus the bar's
axial force there is the load) and shares the load between bar and concrete as the transformed
section says, n rho / (1 + n rho); the bar views are read-only views of the solver's storage; a
pull resumed from a checkpoint keeps the bits; bad values are refused naming them.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_tie.py
"""
import numpy as np
import pytest

import tessera
from tessera import geometry, law, quantity, recorders, reinforcement, stop

B, L = 0.068, 0.3                  # section side and length (m): the study's section, half its length
E_C, NU, RHO = 28e9, 0.2, 2400.0   # the concrete (Pa, -, kg/m^3)
ELEMENTS = 25                      # odd: one element straddles the middle joint at z = L / 2
PULL = 1e-6                        # elongation (m): eps = 3.3e-6, sigma_c = 0.09 MPa, far below f_T


def tie_scene(bars=None, steel=None):
    """Two blocks 0.068 x 0.068 x 0.15 m bonded at z = L / 2 (the Voronoi cells of two generators
    on the axis; the study's joint, Table 1 at 100 blocks), the study's Ø8 mm bar on the axis,
    bonded along its length."""
    tess = geometry.voronoi(tessera.aabb([0, 0, 0], [B, B, L]), [[B / 2, B / 2, L / 4], [B / 2, B / 2, 3 * L / 4]])
    bar = reinforcement.tie_reinforcement([B / 2, B / 2, 0], [B / 2, B / 2, L], ELEMENTS)
    if bars is not None:
        bar.bars = bars
    if steel is not None:
        bar.steel = steel
    return tessera.instances.tie_solver(tess, geometry.zone_blocks(tess),
                                        tessera.zones.linear_elastic_tet.params(E_C, NU, RHO),
                                        law.study_prism_params(100), bar)


@pytest.fixture(scope="module")
def pulled_tie():
    """Both ends of concrete and bar held in z at z = 0, moved together by PULL at z = L (x and y
    free: no end restraint of the Poisson contraction), then held until the load settles."""
    s = tie_scene()
    first, end = s.bar_node_range(0)
    bottom, top = s.gridpoints_on_plane(2, 0.0, 1e-9), s.gridpoints_on_plane(2, L, 1e-9)
    z = tessera.bc.along(2)
    s.fix(bottom, z)
    s.fix_bar_nodes([first], z)
    rate, ramp = 1e-3, PULL / 1e-3  # m/s, s
    s.prescribe_velocity(top, [0, 0, rate], z)
    s.prescribe_bar_velocity([end - 1], [0, 0, rate], z)
    s.run_until(stop.after_time(ramp))
    s.update_velocity(top, [0, 0, 0], z)
    s.update_bar_velocity([end - 1], [0, 0, 0], z)
    r = s.run_until(stop.when_settled(quantity.reaction_sum(bottom, 2), 1e-9, stop.over_steps(5000))
                    | stop.after_steps(2_000_000))
    assert not r.hit_max_steps
    return s


def applied_load(s):
    """The load (N, tension +): the z reactions at z = 0 of the concrete and the bar's first node."""
    first, _ = s.bar_node_range(0)
    bottom = s.gridpoints_on_plane(2, 0.0, 1e-9)
    return -(recorders.reaction_sum(s.gridpoints(), bottom)[2] + s.bar_nodes().reaction[first, 2])


def test_the_middle_joint_and_the_bar_carry_the_load(pulled_tie):
    s = pulled_tie
    P = applied_load(s)
    assert P > 0
    cs = s.contact_state()
    assert cs.size() >= 4 and np.allclose(cs.position[:, 2], L / 2, atol=1e-5)  # the joint's corners at least
    # the joint's sub-contacts: block 1's side (z > L / 2) is pulled back by the force block 0
    # exerts, so the concrete's tension across the joint is minus their z force
    concrete = -np.sum(cs.force[:, 2])
    middle = ELEMENTS // 2  # the element across z = L / 2
    bar = s.bar_axial_force()[middle]
    assert concrete + bar == pytest.approx(P, rel=1e-6)
    assert concrete > 0.9 * P  # the joint is bonded: the concrete carries most of the load across it
    # the reactions at the two ends balance too
    top = s.gridpoints_on_plane(2, L, 1e-9)
    _, end = s.bar_node_range(0)
    pulled = recorders.reaction_sum(s.gridpoints(), top)[2] + s.bar_nodes().reaction[end - 1, 2]
    assert pulled == pytest.approx(P, rel=1e-6)


def test_the_bar_takes_its_transformed_section_share(pulled_tie):
    """Where bar and concrete strain alike, N_s / P = n rho / (1 + n rho) with n = E_s / E_c and
    rho = A_s / B^2 (the modelled concrete fills the gross section): 0.0695. The joint opens by
    sigma_c / k_n (74 nm at 86 kPa), which the bar bridges, so the bar's force rises towards the
    joint over the shear-lag length 1 / lambda = 53 mm (lambda^2 = k_b (1 / E_s A_s + 1 / E_c A_c),
    k_b = xi E_s A_s / L_el). Measured: 0.0711 at the end elements (+2.4 %), 0.0734 a quarter
    length in (+5.6 %), 0.0841 across the joint (+21 %)."""
    s = pulled_tie
    steel = reinforcement.tie_steel()
    n_rho = steel.young_modulus / E_C * steel.area() / (B * B)
    share = n_rho / (1 + n_rho)
    measured = s.bar_axial_force() / applied_load(s)
    print("bar share", measured, "closed form", share)
    assert np.allclose(measured[[0, -1]], share, rtol=0.03)  # the ends, farthest from the joint
    middle = ELEMENTS // 2
    assert np.all(np.diff(measured[: middle + 1]) > 0) and np.all(np.diff(measured[middle:]) < 0)
    assert measured[middle] == pytest.approx(share * 1.21, rel=0.02)
    # the two halves mirror each other about the joint: forces alike, slips opposite (within
    # 0.5 %; measured 0.14 % next to the joint, where the bond hands most load over)
    assert np.allclose(measured, measured[::-1], rtol=5e-3)
    slip = s.bar_slip()
    assert np.abs(slip).max() > 0 and np.allclose(slip, -slip[::-1], rtol=5e-3, atol=0)


def test_the_bar_views_are_read_only_views_of_the_solver(pulled_tie):
    s = pulled_tie
    f = s.bar_axial_force()
    assert f.shape == (ELEMENTS,) and not f.flags.writeable and not f.flags.owndata
    with pytest.raises(ValueError):
        f[0] = 1.0
    assert s.bar_slip().shape == (ELEMENTS + 1,) == s.bar_bond_force().shape
    assert s.bar_nodes().size() == ELEMENTS + 1 and s.bar_count() == 1
    assert s.bar_element_range(0) == (0, ELEMENTS)
    before = f.copy()
    s.step()  # the same storage, updated by the step (the load is held: the forces barely move)
    assert np.allclose(f, before, rtol=1e-6) and f.ctypes.data == s.bar_axial_force().ctypes.data


def test_bad_bar_values_are_refused_naming_them():
    with pytest.raises(tessera.Error, match=r"steel: bar diameter d \(m\).*-0.008"):
        tie_scene(steel=reinforcement.steel(192.3e9, 400e6, -0.008))
    with pytest.raises(tessera.Error, match=r"no bars given"):
        tie_scene(bars=[])
    s = tie_scene()
    with pytest.raises(tessera.Error, match=r"fix_bar_nodes: bar node 26 is outside \[0, 26\)"):
        s.fix_bar_nodes([26])
    with pytest.raises(tessera.Error, match=r"bar_node_range: bar 1 is outside \[0, 1\)"):
        s.bar_node_range(1)
    with pytest.raises(tessera.Error, match=r"update_velocity on node group .bar nodes.: node 0 component x is not prescribed"):
        s.update_bar_velocity([0], [0, 0, 1.0])


def test_a_pull_resumed_from_a_checkpoint_takes_the_same_steps(resumed, tmp_path):
    """The bars' nodes, element and bond states travel in the checkpoint: the resumed pull gives
    the bar forces and gridpoint displacements of the run that never stopped, to the bit."""
    def make():
        s = tie_scene()
        first, end = s.bar_node_range(0)
        z = tessera.bc.along(2)
        s.fix(s.gridpoints_on_plane(2, 0.0, 1e-9), z)
        s.fix_bar_nodes([first], z)
        s.prescribe_bar_velocity([end - 1], [0, 0, 1e-3], z)  # the bar alone pulled: the bond works
        return s
    a, b, info = resumed(make, 300, str(tmp_path / "tie.ckpt"), "tie at 300 steps")
    assert info.description == "tie at 300 steps"
    assert np.abs(a.bar_axial_force()).max() > 0 and np.abs(a.bar_slip()).max() > 0
    assert np.array_equal(a.bar_axial_force(), b.bar_axial_force())
    assert np.array_equal(a.bar_slip(), b.bar_slip())
    assert np.array_equal(a.gridpoints().displacement, b.gridpoints().displacement)
