"""A calibrated parameter file from Python: tessera.calibration reads examples/calibrate's
calibrated.json with the drivers' own reader (examples/common/calibration.hpp), scales the
study's contacts as the drivers do, and refuses what the drivers refuse with their message.

    PYTHONPATH=build/release/python python3 -m pytest python/tests/test_calibration.py
"""
import json
import pathlib

import pytest

import tessera
from tessera import calibration, law

FILE = {
    "format": "tessera-calibration-1",
    "recipe": {"material": "prism", "softening": "power", "cohesion_ratio": 2, "step_displacement_m": 2e-09,
               "rate_m_per_s": 0.005, "rigid": False, "zone_edge_m": 0, "beam_volume_m3": 0},
    "entries": [{"blocks": 100, "strength_scale": 0.907, "fracture_energy_scale": 1.25, "seeds": [1, 2, 3],
                 "initial_modulus_mean_Pa": 2.9e10},
                {"blocks": 250, "strength_scale": 0.95, "fracture_energy_scale": 1}],
}


def write(tmp_path, doc, name="calibrated.json"):
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return str(path)


def test_a_calibrated_file_scales_the_study_contacts_as_the_drivers_do(tmp_path):
    c = calibration.read_calibration(write(tmp_path, FILE))
    assert c.recipe.material == "prism" and c.recipe.softening == "power" and c.recipe.rigid is False
    assert c.recipe.step_displacement == 2e-9 and c.recipe.rate == 0.005
    assert [e.blocks for e in c.entries] == [100, 250]
    e = c.entry_for(100)
    assert (e.strength_scale, e.fracture_energy_scale, e.initial_modulus) == (0.907, 1.25, 2.9e10)
    p = law.study_prism_params(100)
    f_t, g_f = p.tension.f_T, p.tension.G_f
    calibration.scale_prism_contacts(p, e.strength_scale, e.fracture_energy_scale, c.recipe.cohesion_ratio)
    # f_T x s, G_f x s_G, c_0 = 2 x the scaled f_T, c_res = 0.01 c_0: the Table 1 prism's 2.15 MPa, 60 N/m
    assert (f_t, g_f) == (2.15e6, 60.0)
    assert p.tension.f_T == f_t * 0.907 and p.tension.G_f == g_f * 1.25
    assert p.shear.c_0 == 2 * p.tension.f_T and p.shear.c_res == 0.01 * p.shear.c_0
    run = calibration.calibration_recipe()  # the defaults: the prism recipe, power softening, c_0 = 2 f_T
    assert calibration.load_calibration(write(tmp_path, FILE), 250, run).strength_scale == 0.95


def test_a_bad_calibrated_file_is_refused_naming_the_field(tmp_path):
    doc = json.loads(json.dumps(FILE))
    doc["entries"][0]["strength_scale"] = 20
    with pytest.raises(tessera.IoError, match=r"strength_scale = 20 must lie in \[0.1, 10\]"):
        calibration.read_calibration(write(tmp_path, doc))
    doc = json.loads(json.dumps(FILE))
    doc["format"] = "other-1"
    with pytest.raises(tessera.IoError, match=r"format 'other-1', expected 'tessera-calibration-1'"):
        calibration.read_calibration(write(tmp_path, doc))
    with pytest.raises(tessera.InvalidInput, match=r"has no entry for 500 blocks \(it has 100, 250\)"):
        calibration.read_calibration(write(tmp_path, FILE)).entry_for(500)
    rigid = calibration.calibration_recipe()
    rigid.rigid = True
    with pytest.raises(tessera.InvalidInput, match=r"was fitted with deformable blocks, this run uses rigid ones"):
        calibration.load_calibration(write(tmp_path, FILE), 100, rigid, "test")
    ratio = calibration.calibration_recipe()
    ratio.cohesion_ratio = 3
    with pytest.raises(tessera.InvalidInput, match=r"was fitted with cohesion ratio 2, this run uses 3"):
        calibration.load_calibration(write(tmp_path, FILE), 100, ratio, "test")


def test_a_whole_concrete_set_reads_every_field():
    # tests/data/concrete_beam_slip.json: the slip-softening set that meets compression (calibrate --targets writes these fields)
    path = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "concrete_beam_slip.json"
    e = calibration.read_calibration(str(path)).entry_for(250)
    assert (e.law, e.cohesion_ratio, e.phi_0_deg, e.phi_res_deg, e.g_ii, e.cap) == ("slip_softening", 2, 58, 15, 300, 100e6)
    assert calibration.read_calibration(str(path)).recipe.material == "beam"
