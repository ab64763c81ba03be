"""Checks calibrate --targets shear against rc_beam (tests/example_tests.cmake,
example_calibrate_targets_shear_matches_rc_beam).

argv: the calibrate example's output directory (seed 2 fitted, failure reached; seed 3 held out, not
reached) and rc_beam's on seed 2 with the same beam flags. Passes when calibrate's figure is rc_beam's
to the bit (P at failure, the hand reference, their ratio), and the held-out seed that did not fail has
residual exactly unreached_residual (10) and 'not met' in residuals.csv.
"""
import csv
import json
import sys

calibrate = json.load(open(sys.argv[1] + "/summary.json"))
beam = json.load(open(sys.argv[2] + "/summary.json"))
rows = {r["target"]: r for r in csv.DictReader(open(sys.argv[1] + "/residuals.csv"))}
shear = rows["shear"]
reference = 0.5 * (beam["hand_ec2_shear_load_N"] + beam["hand_zsutty_shear_load_N"])
checks = {
    "rc_beam failure reached": beam["failure_reached"] is True,
    "P at failure to the bit": calibrate["fit_shear_value"] == beam["peak_load_N"],
    "reference to the bit": calibrate["shear_reference"] == reference,
    "ratio to the bit": calibrate["fit_shear_value"] / calibrate["shear_reference"] == beam["peak_over_shear_reference"],
    "residuals.csv reference": abs(float(shear["reference"]) / reference - 1) < 1e-9,
    "held-out residual 10": float(shear["holdout_residual"]) == 10.0,
    "held-out not met": shear["holdout_met"] == "not met",
    "held-out not reached": shear["holdout_reached"] == "0" and shear["holdout_runs"] == "1",
}
print(calibrate["fit_shear_value"], beam["peak_load_N"], calibrate["shear_reference"], reference, dict(shear))
for name, ok in checks.items():
    print(("ok   " if ok else "FAIL ") + name)
sys.exit(0 if all(checks.values()) else 1)
