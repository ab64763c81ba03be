#!/usr/bin/env python3
"""The README's arch (tests/consumer/arch.cpp) driven from Python: a semicircular masonry arch of
20 voussoirs on dry joints, standing under its own weight. The arch is 0.4 m thick on a 2.2 m mean
radius (t/R = 0.18, above Heyman's least thickness 0.106), so it must stand: the run must settle,
the held base must carry the whole weight, and the crown must sag by less than a millimetre.

    PYTHONPATH=build/release/python python3 examples/python/arch.py

Prints the C++ program's summary and writes its arch.csv (the crown's z displacement and the
base's z reaction every 200 steps, 17 significant digits), with the same bits, and exits 1 if a
check fails.
"""
import math
import sys

import tessera
from tessera import geometry, law, quantity, recorders, stop


def run_arch(record=None):
    """Builds and runs the arch; returns (solver, run_result, weight N, crown index). record(s),
    when given, is called after every 200th step (and before the first), as the C++ recorder (rows at steps 0, 200, 400, ...)."""
    # 1. geometry: a base slab (block 0) and 20 voussoirs between radii 2.0 and 2.4 m, 1 m deep
    n = 20
    blocks = [geometry.convex_polyhedron.box([-3, -0.5, -0.5], [3, 0.5, 0])]
    for k in range(n):
        blocks.append(geometry.voussoir([0, 0, 0], 2.0, 2.4, math.pi * k / n, math.pi * (k + 1) / n, 1.0))
    tess = geometry.separate_blocks(blocks)  # cell b is blocks[b]
    mesh = geometry.zone_blocks(tess)

    # 2. materials: stone of 2400 kg/m^3 on dry joints (k_n = k_s = 10 GPa/m, friction 35 deg)
    joint = tessera.contact.detected_dry_joints(law.dry_joint(1e10, 1e10, law.friction_angle.from_degrees(35)),
                                                tolerance=1e-3)  # m
    s = tessera.instances.rigid_dry_damped_solver(tess, mesh, tessera.blocks.rigid.params(2400), joint)

    # 3. supports and loading: the base slab held, gravity
    s.fix_blocks(s.blocks_below(2, 0.0))
    s.set_gravity([0, 0, -9.81])

    # 4. run until the crown settles (or falls, or 3 s pass), recording it
    crown = n // 2  # the voussoir right of the key joint
    until = (stop.when_settled(quantity.block_displacement(crown, 2), 1e-8, stop.over_time(0.05))
             | stop.when_beyond(quantity.block_displacement_magnitude(crown), 0.05)
             | stop.after_time(3.0))
    if record is not None:  # a condition that never holds, checked every 200 steps
        until = until | stop.when(lambda solver: bool(record(solver)) and False, "recording", every=200)
    r = s.run_until(until, 100_000_000)

    # 5. the weight of every block (its own and the arch's), summed in the C++ program's order
    weight = 0.0
    for b in range(n + 1):
        weight += s.blocks().weight_mass(b) * 9.81
    return s, r, weight, crown


def main():
    crown = 10
    rows = ["step,time_s,uz_crown_m,Rz_base_N\n"]

    def record(s):
        rz = recorders.reaction_sum(s.gridpoints(), s.gridpoints_of_block(0))[2]
        rows.append("%d,%.17g,%.17g,%.17g\n" % (s.step_count(), s.time(), s.block_displacement(crown)[2], rz))

    s, r, weight, crown = run_arch(record)
    with open("arch.csv", "w") as f:
        f.writelines(rows)
    base = recorders.reaction_sum(s.gridpoints(), s.gridpoints_of_block(0))[2]
    sag = -s.block_displacement(crown)[2]
    print("%d steps of %.3g s: %s\nbase reaction %.6g N against the weight %.6g N; crown sag %.3g mm"
          % (r.steps, s.dt(), r.reason, base, weight, sag * 1e3))
    ok = (not r.hit_max_steps and r.reason.startswith("settled") and abs(base - weight) < 1e-3 * weight
          and abs(sag) < 1e-3)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
