"""Loads, stresses and checkpoints from Python on the deformable solver: applied forces balance
the support reactions and give the column's elastic shortening, zone stresses of a homogeneous
strain are Hooke's law's, a run resumed from a checkpoint takes the same steps to the bit, and
bad values are refused naming them.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_loads_and_state.py
"""
import pathlib

import numpy as np
import pytest

import tessera
from tessera import geometry, law, quantity, recorders, stop

DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data"
E, NU, RHO = 30e9, 0.2, 2400.0


def column(size=(0.1, 0.1, 1.0)):
    """One deformable block, lo at the origin (m)."""
    tess = geometry.separate_blocks([geometry.convex_polyhedron.box([0, 0, 0], list(size))])
    s = tessera.instances.prism_solver(tess, geometry.zone_blocks(tess), tessera.zones.linear_elastic_tet.params(E, NU, RHO),
                                       law.study_prism_params(100))
    return s


def test_applied_forces_balance_the_reactions_and_shorten_the_column():
    L, A, F = 1.0, 0.01, 1e5  # m, m^2, N (compression)
    s = column()
    bottom, top = s.gridpoints_on_plane(2, 0.0, 1e-9), s.gridpoints_on_plane(2, L, 1e-9)
    s.fix(bottom)
    s.register_applied_forces(top)
    assert list(s.applied_nodes()) == list(top.nodes)
    f = s.applied_forces()  # a writable view of the solver's array (gridpoints x 3)
    assert f.shape == (s.gridpoints().size(), 3) and f.flags.writeable
    f[top.nodes, 2] = -F / len(top)
    r = s.run_until(stop.when_settled(quantity.mean_displacement(top, 2), 1e-13, stop.over_steps(2000))
                    | stop.after_steps(400_000))
    assert not r.hit_max_steps
    g = s.gridpoints()
    # equilibrium: the bottom's reaction carries the load (the rows written stay applied)
    assert recorders.reaction_sum(g, bottom)[2] == pytest.approx(F, rel=1e-6)
    assert np.allclose(s.applied_forces()[top.nodes, 2], -F / len(top), rtol=0)
    # the shortening F L / (E A) = 0.333 um; the fixed base's Poisson restraint and the corner
    # loads of a coarse zoning stiffen the column a little (measured: see the assert's band)
    shortening = -recorders.mean_displacement(g, top)[2]
    assert shortening == pytest.approx(F * L / (E * A), rel=0.1)
    # the loads' work enters the energy balance
    assert abs(s.energies().error_rel()) < 1e-3


def test_applied_forces_refuse_bad_stiffnesses_naming_them():
    s = column()
    top = s.gridpoints_on_plane(2, 1.0, 1e-9)
    with pytest.raises(tessera.Error, match=r"stiffness -1 N/m on gridpoint \d+ must be finite and >= 0"):
        s.register_applied_forces(top, -1.0)
    with pytest.raises(tessera.Error, match=r"got %d gridpoints and 2 stiffnesses" % len(top)):
        s.register_applied_forces(top, [1.0, 2.0])


def test_zone_stress_of_a_homogeneous_strain_is_hookes_law():
    """Every gridpoint driven at v_z = rate z / L, x and y held: uniaxial strain eps = u / L in
    every zone, sigma_zz = (lambda + 2 mu) eps, sigma_xx = sigma_yy = lambda eps, no shear."""
    L, rate = 1.0, 1e-3
    s = column()
    z = s.gridpoints().reference[:, 2].copy()
    for level in np.unique(z):
        s.prescribe_velocity(s.gridpoints_on_plane(2, float(level), 1e-12), [0, 0, rate * level / L])
    s.run_until(stop.after_steps(50))
    u = s.gridpoints().displacement
    top = s.gridpoints_on_plane(2, L, 1e-9)
    eps = float(u[top.nodes[0], 2]) / L  # the strain of the displacement the stresses were formed from
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    sigma = s.zone_stress()
    assert sigma.shape[1] == 6 and sigma.shape[0] >= 6
    assert not sigma.flags.writeable
    # the stresses are those of the last step's forces: the displacement one step before the last
    eps_formed = eps * 49 / 50
    assert np.allclose(sigma[:, 2], (lam + 2 * mu) * eps_formed, rtol=1e-9, atol=0)
    assert np.allclose(sigma[:, 0], lam * eps_formed, rtol=1e-9, atol=0)
    assert np.allclose(sigma[:, 1], lam * eps_formed, rtol=1e-9, atol=0)
    assert np.abs(sigma[:, 3:]).max() < 1e-9 * sigma[:, 2].max()


def two_cells():
    """tests/data/two_cells.tess (two bonded half cubes, 1 m^3), bottom held, top pulled up."""
    tess = tessera.io.read_neper_tess(str(DATA / "two_cells.tess"))
    options = tessera.solver_options()
    options.mass_scaling_dt = 1e-5
    s = tessera.instances.prism_solver(tess, geometry.zone_blocks(tess), tessera.zones.linear_elastic_tet.params(E, NU, RHO),
                                       law.study_prism_params(100), options=options)
    s.fix(s.gridpoints_on_plane(2, 0.0, 1e-9))
    s.prescribe_velocity(s.gridpoints_on_plane(2, 1.0, 1e-9), [0, 0, 1e-4])
    return s


def state_of(s):
    g, cs = s.gridpoints(), s.contact_state()
    return (s.step_count(), s.time(), np.array(g.displacement), np.array(g.velocity), cs.field("sigma_n_Pa"),
            cs.tensile_damage, s.energies().boundary_work)


def same(a, b):
    return all(np.array_equal(x, y) for x, y in zip(a, b))


def test_neper_tessellation_reads_with_its_cells_volumes_and_mass():
    tess = tessera.io.read_neper_tess(str(DATA / "two_cells.tess"))
    assert (tess.cell_count(), tess.vertex_count(), tess.face_count()) == (2, 12, 12)
    s = two_cells()
    assert s.block_count() == 2
    # the lumped masses hold the 1 m^3 cube's mass, rho V = 2400 kg
    assert s.mass_scaling().original_mass == pytest.approx(RHO * 1.0, rel=1e-12)
    assert s.contact_count() > 0


def test_neper_refuses_a_missing_or_bad_file_naming_it(tmp_path):
    with pytest.raises(tessera.IoError, match=r"cannot open '.*nowhere.tess'"):
        tessera.io.read_neper_tess(str(tmp_path / "nowhere.tess"))
    bad = (DATA / "two_cells.tess").read_text().replace("**cell\n   2", "**cell\n   -2", 1)
    (tmp_path / "bad.tess").write_text(bad)
    with pytest.raises(tessera.IoError, match=r"read_neper_tess: .*bad.tess:\d+"):
        tessera.io.read_neper_tess(str(tmp_path / "bad.tess"))


def test_a_run_resumed_from_a_checkpoint_takes_the_same_steps_to_the_bit(tmp_path, resumed):
    path = str(tmp_path / "half.ckpt")
    a, b, info = resumed(two_cells, 300, path, "two cells at step 300")
    assert info.description == "two cells at step 300" and info.version == tessera.__version__
    assert tessera.io.read_checkpoint_info(path).records == info.records > 0
    assert same(state_of(a), state_of(b))
    assert a.energies().boundary_work > 0  # the pull did work: the compared state is not at rest


def test_a_checkpoint_that_does_not_fit_is_refused_naming_the_record(tmp_path):
    path = str(tmp_path / "c.ckpt")
    tessera.io.save_checkpoint(column(), path)
    b = two_cells()
    before = state_of(b)
    # the first record that differs is named, with both values
    with pytest.raises(tessera.InvalidInput, match=r"does not fit this model: solver/dt = [0-9.e+-]+ in the file but "
                                                   r"1e-05 in this model"):
        tessera.io.load_checkpoint(b, path)
    assert same(before, state_of(b))  # refused before anything changed
    with pytest.raises(tessera.IoError):
        tessera.io.load_checkpoint(b, str(tmp_path / "none.ckpt"))
