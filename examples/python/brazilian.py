#!/usr/bin/env python3
"""The Brazilian splitting test of a concrete disc (examples/brazilian, --material prism) driven
from Python: a disc D x t = 150 x 60 mm (axis z) as a 36-gon prism with flats at y = +-a, the
study's prism concrete (Table 1 contacts at 100 blocks times the strength scale 0.907, c_0 = 2 f_T,
phi_0 = 35 deg) at the prism's block size (38 random Voronoi blocks, seed 1), one zone per face
triangle, semi-rigid blocks (E = 10 x 28 GPa). Bottom flat (the loading strip) held, top flat
pushed down at 5 mm/s, masses scaled so a step moves it du (2 nm; --quick: 5 nm).

    PYTHONPATH=build/release/python python3 examples/python/brazilian.py --quick --out results/py_brazilian

Writes curve.csv (strip displacement m, top and bottom loads N, opening across the loaded
diameter m; 17 digits) with the bits of `brazilian --quick --threads 1` (or without --quick,
of the driver without it), summary.json (P_max, the split, f_sp = 2 P_max / (pi D t)) and
run.json; prints f_sp / f_T. A disc not split by --max-displacement reports no f_sp. Exits 1 if
a split disc's f_sp / f_T lies outside the driver's CTest band 1.8-3.0.
"""
import argparse
import json
import math
import sys

import numpy as np

import tessera
from tessera import geometry, law, recorders, stop

CONCRETE_YOUNG, CONCRETE_POISSON, CONCRETE_DENSITY = 28e9, 0.2, 2400.0  # examples/common/scenes.hpp
SEMI_RIGID_FACTOR = 10  # E_block = 10 E
PRISM_CELL_VOLUME = 0.068 * 0.068 * 0.6 / 100  # the 100-block prism's mean block volume (m^3)
HINGE_DROP = 0.9  # disc.hpp's hinge_drop: halves that turn apart about a chain beside a strip have split


def cpp_round(x):
    """std::round: halves away from zero (Python's round() takes halves to even)."""
    return math.copysign(math.floor(abs(x) + 0.5), x)


def prism_concrete(strength_scale=0.907, cohesion_ratio=2.0):
    """scenes::prism_concrete: the 100-block prism's contacts, f_T x strength_scale, c_0 =
    cohesion_ratio f_T, c_res = 0.01 c_0; and the concrete's f_T (Pa), the unscaled one."""
    contact = law.scaled_prism_params(100)
    f_t = contact.tension.f_T
    contact.tension.f_T *= strength_scale
    contact.shear.c_0 = cohesion_ratio * contact.tension.f_T
    contact.shear.c_res = 0.01 * contact.shear.c_0
    return contact, f_t


class disc_run:
    """The disc of examples/brazilian/main.cpp (run_disc, the prism's concrete): the scene, and
    what the driver does every `every` steps (observe), until the split or --max-displacement."""

    def __init__(self, quick=True, seed=1, threads=1, sides=36, diameter=0.15, thickness=0.06, rate=5e-3,
                 step_displacement=2e-9, max_displacement=3e-4, phi_deg=35.0):
        du = max(step_displacement, 5e-9) if quick else step_displacement
        self.rate, self.du, self.u_max, self.diameter, self.thickness = rate, du, max_displacement, diameter, thickness
        pi = math.pi
        R = diameter / 2
        self.a = a = R * math.cos(pi / sides)
        self.strip = 2 * R * math.sin(pi / sides)
        # 1. geometry: the 36-gon disc (a face across x and y: the strips at y = +-a), Voronoi blocks
        disc = geometry.cylinder_prism([0, 0, 0], [0, 0, 1], R, thickness, sides, pi / sides)
        disc_volume = 0.5 * sides * R * R * math.sin(2 * pi / sides) * thickness
        self.blocks = max(2, int(cpp_round(disc_volume / PRISM_CELL_VOLUME)))  # the prism's block size
        # 2. materials: the prism's concrete, phi_0 from the flag
        joint, self.f_t = prism_concrete()
        joint.shear.phi_0 = law.friction_angle.from_degrees(phi_deg)
        joint.validate()
        self.tess = geometry.random_voronoi(disc, self.blocks, seed)
        zoning = geometry.zoning_options()
        zoning.target_edge_length, zoning.refine_interior = 0.0, True  # one zone per face triangle
        self.mesh = geometry.zone_blocks(self.tess, zoning)
        concrete = tessera.zones.linear_elastic_tet.params(SEMI_RIGID_FACTOR * CONCRETE_YOUNG, CONCRETE_POISSON,
                                                           CONCRETE_DENSITY)
        # 3. the solver: masses scaled so the strip moves du per step
        options = tessera.solver_options()
        options.mass_scaling_dt = du / rate
        options.threads = threads
        s = self.s = tessera.instances.prism_solver(self.tess, self.mesh, concrete, tessera.contact.study_tie_table(joint),
                                                    options=options)
        # 4. supports: the bottom strip held, the top strip pushed down at the rate
        tol = 1e-9 * diameter
        self.bottom, self.top = s.gridpoints_on_plane(1, -a, tol), s.gridpoints_on_plane(1, a, tol)
        s.fix(self.bottom)
        s.prescribe_velocity(self.top, [0, -rate, 0])
        # the split: no chain of intact contacts joins a block on the flat x = -a to one on x = +a across
        # the middle two thirds, or (once the load has fallen to HINGE_DROP of its largest) the middle third
        self.left, self.right = s.blocks_on_plane(0, -a, tol), s.blocks_on_plane(0, a, tol)
        # the opening: gridpoints on the flats x = +-a over the middle third of the height
        x = s.gridpoints().reference
        on_flat = (np.abs(np.abs(x[:, 0]) - a) <= tol) & (np.abs(x[:, 1]) < diameter / 6)
        self.flank = [np.flatnonzero(on_flat & (x[:, 0] <= 0)), np.flatnonzero(on_flat & (x[:, 0] > 0))]
        if len(self.flank[0]) == 0 or len(self.flank[1]) == 0:
            raise tessera.InvalidInput("brazilian.py: no gridpoint on the flats x = +-a across the middle")
        self.every = int(max(1, cpp_round(2e-7 / du)))  # a sample per 0.2 um
        self.curve = []  # rows: u, P_top, P_bottom, opening
        self.p_max = self.u_peak = self.p_bottom_at_peak = self.u_split = self.p_split = self.w_split = 0.0
        self.split_by_hinge = False  # found in the middle third after the load fell
        self.done = False

    def split(self, s, band):
        """Whether no chain of intact sub-contacts (tensile damage < 0.5, not slipped) within
        |y| < band (m) joins a block on the flat x = -a to one on x = +a."""
        cs = s.contact_state()
        slipped = int(law.contact_status.slipped)
        intact = ((np.abs(cs.position[:, 1]) < band) & (cs.tensile_damage < 0.5)
                  & ((cs.status & slipped) == 0))
        root = list(range(s.block_count()))

        def find(b):
            while root[b] != b:
                root[b] = root[root[b]]
                b = root[b]
            return b

        n = len(root)
        for key in np.unique(cs.block_a[intact] * n + cs.block_b[intact]).tolist():  # each joined pair once
            root[find(key // n)] = find(key % n)
        return not {find(b) for b in self.left} & {find(b) for b in self.right}

    def opening(self, s):
        """Mean x displacement on the flat x = +a minus that on x = -a (m), summed in order as
        the driver sums it."""
        u = s.gridpoints().displacement
        w = 0.0
        for k, sign in ((0, -1), (1, 1)):
            mean = 0.0
            for g in self.flank[k]:
                mean += float(u[g, 0])
            w += sign * mean / len(self.flank[k])
        return w

    def observe(self, s):
        g = s.gridpoints()
        p, pb = -recorders.reaction_sum(g, self.top)[1], recorders.reaction_sum(g, self.bottom)[1]
        u = self.rate * s.time()
        w = self.opening(s)
        self.curve.append((u, p, pb, w))
        if p > self.p_max and self.u_split == 0:
            self.p_max, self.u_peak, self.p_bottom_at_peak = p, u, pb
        if self.u_split == 0:
            d = self.diameter
            across = self.split(s, d / 3)
            if across or (p <= HINGE_DROP * self.p_max and self.split(s, d / 6)):
                self.u_split, self.p_split, self.w_split, self.split_by_hinge = u, p, w, not across
        self.done = u >= self.u_max or (self.u_split > 0 and u > 1.2 * self.u_split)

    def run(self):
        """Steps until done: the driver's observer after every `every`-th step, its stop rule."""
        def sample(sv):
            if sv.step_count() > 0:
                self.observe(sv)
            return self.done

        self.result = self.s.run_until(stop.when(sample, "split or the last displacement", every=self.every),
                                       int(2 * self.u_max / self.du))
        return self

    def summary(self):
        did_split = self.u_split > 0
        f_sp = 2 * self.p_max / (math.pi * self.diameter * self.thickness) if did_split else None
        return {"example": "brazilian.py", "material": "prism", "blocks": self.blocks, "du_m": self.du,
                "dt_s": self.s.dt(), "steps": self.s.step_count(), "split": did_split, "split_by_hinge": self.split_by_hinge,
                "peak_load_N": self.p_max if did_split else None, "largest_load_N": self.p_max,
                "peak_displacement_m": self.u_peak, "split_displacement_m": self.u_split if did_split else None,
                "split_load_N": self.p_split if did_split else None, "f_sp_Pa": f_sp, "f_T_Pa": self.f_t,
                "f_sp_over_f_T": f_sp / self.f_t if did_split else None,
                "bottom_over_top_at_peak_rel": (self.p_max - self.p_bottom_at_peak) / self.p_max,
                "energy_balance_error_rel": self.s.energies().error_rel()}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default="results/python_brazilian", help="output folder")
    p.add_argument("--quick", action="store_true", help="5 nm per step (the driver's --quick)")
    p.add_argument("--seed", type=int, default=1, help="tessellation seed")
    p.add_argument("--threads", type=int, default=1, help="OpenMP threads (the same bits for any count)")
    p.add_argument("--max-displacement", type=float, default=3e-4, help="last strip displacement (m)")
    a = p.parse_args(argv)
    with tessera.run_record(a.out, "brazilian.py", sys.argv[1:] if argv is None else argv) as record:
        run = disc_run(quick=a.quick, seed=a.seed, threads=a.threads, max_displacement=a.max_displacement).run()
        tessera.io.write_csv(record.file("curve.csv"), ["u_m", "P_top_N", "P_bottom_N", "opening_m"],
                             list(zip(*run.curve)))  # columns, 17 digits: the C++ file
        summary = run.summary()
        with open(record.file("summary.json"), "w") as f:
            json.dump(summary, f, indent=1)
    if not summary["split"]:
        print("brazilian.py: %d blocks, seed %d did NOT split by %.1f um: no f_sp (largest load %.2f kN); %d steps"
              % (run.blocks, a.seed, a.max_displacement * 1e6, run.p_max * 1e-3, run.s.step_count()))
        return 0
    ratio = summary["f_sp_over_f_T"]
    print("brazilian.py: %d blocks, seed %d, P_max %.2f kN at %.1f um (split at %.1f um), f_sp %.3f MPa = %.3f f_T, "
          "%d steps; wrote %s" % (run.blocks, a.seed, run.p_max * 1e-3, run.u_peak * 1e6, run.u_split * 1e6,
                                  summary["f_sp_Pa"] * 1e-6, ratio, run.s.step_count(), a.out))
    return 0 if 1.8 < ratio < 3.0 else 1


if __name__ == "__main__":
    sys.exit(main())
