#!/usr/bin/env python3
"""The reference study's RC beam in four-point bending (examples/rc_beam's default scene) driven
from Python on tessera.instances.beam_solver: the half beam (Walraven's series-A1 beam,
PROVISIONAL as in the driver: b 200, h 150, d 125 mm, support 100 mm from the end, shear span
375 mm, half the 500 mm constant-moment zone) with a symmetry face at mid-span, random Voronoi
blocks of semi-rigid concrete (10 x 25 GPa) on bonded faces with the study's beam law
(law.study_beam_params), 4 bars of 8 mm (210 GPa, 440 MPa) with the tie's bond, and two rigid
steel plates of their own (contact.rigid_platen, hinged, rolling in x): the support plate held,
the loading plate driven down at 5 mm/s after a half-cosine ramp over the first bending mode's
period, masses scaled to 20 x the model's mass added.

    PYTHONPATH=build/release/python python3 examples/python/rc_beam.py --quick --max-deflection 1e-4 --out results/py_rc_beam

Writes curve.csv (the driver's five columns: mid-span deflection m, load P = 2 x the support
plate's force N, P smoothed over 0.02 mm of deflection, 2 x the loading plate's force N, the
loading plate's travel m; a row every 50 steps, 17 digits), summary.json and run.json. The
script stops at --max-deflection only: the driver also stops once its crack analysis
(examples/rc_beam/beam_cracks.hpp, not in the module) finds a vertical crack h/4 deep (--quick:
at twice that crack's deflection) or the load falls past the peak, so the two curve.csv files
are the same bits up to the driver's stop: `rc_beam --quick --threads 1 --max-deflection 1e-4`
and this script with the same flags (python/tests/test_beam.py).
"""
import argparse
import json
import math
import sys

import numpy as np

import tessera
from tessera import bc, contact, geometry, instances, law, reinforcement, stop

# examples/rc_beam/beam.hpp beam_options' defaults (m), the concrete and steel (Pa, kg/m^3)
WIDTH, HEIGHT, DEPTH, OVERHANG, SHEAR_SPAN, MOMENT_ZONE = 0.2, 0.15, 0.125, 0.1, 0.375, 0.5
PLATE, PLATE_THICKNESS, BARS, BAR_DIAMETER, END_COVER, TRUSSES_PER_BLOCK = 0.05, 0.02, 4, 0.008, 0.02, 4.0
CONCRETE_YOUNG, STEEL_YOUNG, STEEL_YIELD, DENSITY = 25e9, 210e9, 440e6, 2400.0
RATE, ADDED_MASS, GAMMA, SAMPLE, SMOOTHING = 5e-3, 20.0, 0.8, 50, 2e-5  # beam_loading's (m/s, -, -, steps, m)


def cpp_round(x):
    """std::llround: halves away from zero (Python's round() takes halves to even)."""
    return int(math.copysign(math.floor(abs(x) + 0.5), x))


def hand_stiffness():
    """beam_hand's initial stiffness K_0 (N/m): the uncracked transformed section in bending
    plus shear (kappa 5/6, G = E / 2.4), each operation in the driver's order (its bits)."""
    b, hh, d, a = WIDTH, HEIGHT, DEPTH, SHEAR_SPAN
    span = 2 * (OVERHANG + SHEAR_SPAN + 0.5 * MOMENT_ZONE - OVERHANG)
    a_s = BARS * math.pi * BAR_DIAMETER * BAR_DIAMETER / 4
    n = STEEL_YOUNG / CONCRETE_YOUNG
    area = b * hh + (n - 1) * a_s
    yc = (b * hh * hh / 2 + (n - 1) * a_s * d) / area
    inertia = b * hh * hh * hh / 12 + b * hh * (hh / 2 - yc) * (hh / 2 - yc) + (n - 1) * a_s * (d - yc) * (d - yc)
    E, G = CONCRETE_YOUNG, CONCRETE_YOUNG / (2 * 1.2)
    compliance = 0.5 * a * (3 * span * span - 4 * a * a) / (24 * E * inertia) + 0.5 * a / (5.0 / 6.0 * G * b * hh)
    return 1 / compliance


class beam_run:
    """examples/rc_beam/beam_run.hpp run_beam for the default half beam with contact plates."""

    def __init__(self, blocks=250, zone_edge=0.0, seed=1, threads=1, max_deflection=6e-3):
        L = OVERHANG + SHEAR_SPAN + 0.5 * MOMENT_ZONE  # the symmetry face
        self.max_deflection, self.blocks = max_deflection, blocks
        self.box = tessera.aabb([0, 0, 0], [L, HEIGHT, WIDTH])
        self.tess = geometry.random_voronoi(self.box, blocks, seed)
        zoning = geometry.zoning_options()
        zoning.target_edge_length = zone_edge if zone_edge > 0 else HEIGHT / 5
        zoning.refine_interior = False  # the faces zoned, the interior left coarse
        self.mesh = geometry.zone_blocks(self.tess, zoning)
        concrete = tessera.zones.linear_elastic_tet.params(10 * CONCRETE_YOUNG, 0.2, DENSITY)
        joints = law.study_beam_params(500 if blocks >= 500 else 250)
        # the bars: 4 across the width at y = h - d from the end cover to the symmetry face
        mean_block = math.cbrt(L * HEIGHT * WIDTH / blocks)
        elements = max(2, cpp_round(TRUSSES_PER_BLOCK * (L - END_COVER) / mean_block))
        y = HEIGHT - DEPTH
        bars = [reinforcement.bar([END_COVER, y, WIDTH * (2 * i + 1) / (2.0 * BARS)],
                                  [L, y, WIDTH * (2 * i + 1) / (2.0 * BARS)], elements) for i in range(BARS)]
        steel = reinforcement.embedded_truss_params(reinforcement.steel(STEEL_YOUNG, STEEL_YIELD, BAR_DIAMETER),
                                                    reinforcement.tie_bond(), bars)
        options = tessera.solver_options()
        options.mass_scaling_ratio, options.threads, options.damping_gamma = ADDED_MASS, threads, GAMMA
        s = self.s = instances.beam_solver(self.tess, self.mesh, concrete, joints, steel, options)
        # the plates: the plate-concrete pair frictional at 35 deg, no cohesion, never bonded
        pair = law.study_beam_params(500 if blocks >= 500 else 250)
        pair.shear.c_res = 0.0
        pair.shear.phi_res = law.friction_angle.from_degrees(35)
        if pair.shear.phi_res.radians() > pair.shear.phi_0.radians():
            pair.shear.phi_0 = pair.shear.phi_res
        mass = 7850 * PLATE * WIDTH * PLATE_THICKNESS
        motion = contact.platen_motion(mass=mass, inertia=mass * (PLATE * PLATE / 12 + PLATE_THICKNESS * PLATE_THICKNESS / 3),
                                       free_translation=[True, False, False], hinge_axis=[0, 0, 1], damping_gamma=GAMMA)
        tol, z = 1e-9 * L, 0.5 * WIDTH
        self.support = contact.rigid_platen(self.mesh, contact.platen_geometry(
            [OVERHANG, 0, z], [0, 1, 0], [1, 0, 0], 0.5 * PLATE, 0.5 * WIDTH, tol), motion, pair)
        self.loading = contact.rigid_platen(self.mesh, contact.platen_geometry(
            [OVERHANG + SHEAR_SPAN, HEIGHT, z], [0, -1, 0], [1, 0, 0], 0.5 * PLATE, 0.5 * WIDTH, tol), motion, pair)
        self.support.attach(s)
        self.loading.attach(s)
        ms = s.mass_scaling()
        self.added = ms.added_mass / ms.original_mass if ms.original_mass > 0 else 0.0
        # supports: the symmetry face and the bars' last nodes rolling on it
        s.fix(s.gridpoints_on_plane(0, L, tol), bc.along(0))
        for i in range(BARS):
            s.fix_bar_nodes([s.bar_node_range(i)[1] - 1], bc.along(0))
        ref = s.gridpoints().reference
        self.midspan = np.flatnonzero((np.abs(ref[:, 0] - L) <= tol) & (np.abs(ref[:, 1]) <= tol)).tolist()
        # the ramp: the first bending mode's period with the scaled masses (beam_first_mode_period)
        whole_mass = 2 * self.box.volume() * DENSITY
        self.ramp = 2 * math.pi * math.sqrt(whole_mass * (1 + self.added) / (2 * hand_stiffness()))
        self.window = max(1, cpp_round(SMOOTHING / (RATE * s.dt() * SAMPLE)))
        self.curve, self.loads, self.window_sum, self.done = [], [], 0.0, False
        self.drive(s)  # the plates' forces for the first step

    def drive(self, s):
        """Before each step: the loading plate moved down at the ramped rate, both plates updated."""
        t = s.time() + 0.5 * s.dt()
        v = RATE if t >= self.ramp else 0.5 * RATE * (1 - math.cos(math.pi * t / self.ramp))
        self.loading.set_velocity([0, -v, 0])
        self.loading.update(s)
        self.support.update(s)

    def sample(self, s):
        """Every SAMPLE steps: a curve row, summed in the driver's order; the stop."""
        u = s.gridpoints().displacement
        deflection = 0.0
        for g in self.midspan:
            deflection += float(u[g, 1])
        deflection = -deflection / len(self.midspan)
        load = 2 * -self.support.force()[1]
        loads = self.loads
        loads.append(load)
        self.window_sum += load  # the running mean over the last `window` samples, as the driver keeps it
        if len(loads) > self.window:
            self.window_sum -= loads[len(loads) - 1 - self.window]
        smoothed = self.window_sum / min(self.window, len(loads))
        self.curve.append((deflection, load, smoothed, -2 * -self.loading.force()[1], -self.loading.displacement()[1]))
        self.done = deflection >= self.max_deflection

    def run(self):
        def per_step(sv):  # evaluated before every step: the driver's work after the last one
            if sv.step_count() > 0:
                self.drive(sv)
                if sv.step_count() % SAMPLE == 0:
                    self.sample(sv)
            return self.done

        self.result = self.s.run_until(stop.when(per_step, "the last deflection", every=1))
        return self


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default="results/python_rc_beam", help="output folder")
    p.add_argument("--quick", action="store_true", help="the driver's --quick scene: 60 blocks, 50 mm face zoning")
    p.add_argument("--blocks", type=int, help="Voronoi blocks of the half beam (250; --quick 60)")
    p.add_argument("--seed", type=int, default=1, help="tessellation seed")
    p.add_argument("--threads", type=int, default=1, help="OpenMP threads (the same bits for any count)")
    p.add_argument("--max-deflection", type=float, help="stop at this mid-span deflection (m; 6e-3, --quick 2e-3)")
    a = p.parse_args(argv)
    blocks = a.blocks or (60 if a.quick else 250)
    last = a.max_deflection if a.max_deflection is not None else (2e-3 if a.quick else 6e-3)
    if not (8 <= blocks <= 250 or blocks == 500):  # the driver's refusal (beam.hpp make_beam)
        p.error("--blocks %d must be 250 or 500 (the study's Table 3), or 8..249 for a coarse run" % blocks)
    if not last > 0:
        p.error("--max-deflection %g m must be > 0" % last)
    with tessera.run_record(a.out, "rc_beam.py", sys.argv[1:] if argv is None else argv) as record:
        run = beam_run(blocks, 0.05 if a.quick else 0.0, a.seed, a.threads, last).run()
        tessera.io.write_csv(record.file("curve.csv"), ["midspan_deflection_m", "load_N", "smoothed_load_N",
                                                        "plate_load_N", "load_point_deflection_m"], list(zip(*run.curve)))
        s, end = run.s, run.curve[-1]
        summary = {"example": "rc_beam.py", "blocks": blocks, "seed": a.seed, "steps": s.step_count(), "dt_s": s.dt(),
                   "added_mass_ratio": run.added, "ramp_time_s": run.ramp, "deflection_at_stop_m": end[0],
                   "load_at_stop_N": end[1], "peak_load_N": max(row[2] for row in run.curve),
                   "energy_balance_error_rel": s.energies().error_rel()}
        with open(record.file("summary.json"), "w") as f:
            json.dump(summary, f, indent=1)
    print("rc_beam.py: %d blocks, seed %d, P %.2f kN at %.3f mm mid-span deflection, %d steps of %.3g s (added mass "
          "%.1fx); wrote %s" % (blocks, a.seed, end[1] * 1e-3, end[0] * 1e3, s.step_count(), s.dt(), run.added, a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
