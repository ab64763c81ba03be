#!/usr/bin/env python3
"""Block toppling on a stepped base (Goodman & Bray 1976; examples/toppling) driven from Python:
rigid columns of width dx and heights 1, 2, 3, 4, 3 dx (toe first), each on its step of a fixed
base (steps 0.2 dx apart), the base inclined at psi = 20 deg (gravity turned by psi, ramped over
0.2 s), dry joints of friction phi. The limit-equilibrium toe force P_0(phi) gives the critical
friction (P_0 = 0); the simulation is bisected on phi (unstable: a column moves 2 % of dx).

    PYTHONPATH=build/release/python python3 examples/python/toppling.py --quick --out results/py_toppling

Writes regions.csv (phi deg, P_0 N, largest column displacement m; 17 digits) and summary.json
(the critical friction and its bracket) with the C++ driver's bits, and run.json. Exits 1 if the
simulated critical friction is not within 5 % of limit equilibrium's (--quick: -3.5 %).
"""
import argparse
import json
import math
import sys

import tessera
from tessera import geometry, law, quantity, stop

DEG, G = math.pi / 180, 9.81


class scene:
    psi_deg, dx, depth, step, density, k, damping, ramp = 20.0, 0.1, 0.05, 0.2, 2500.0, 1e8, 0.5, 0.2
    heights = [1.0, 2.0, 3.0, 4.0, 3.0]  # column heights (in dx), toe first

    def base(self, n):
        return n * self.step * self.dx

    def top(self, n):
        return self.base(n) + self.heights[n] * self.dx


def simulate(sc, phi_deg, duration):
    """The row at friction phi (deg) until a column moves 2 % of dx, it settles or t = duration:
    (largest column displacement m, why it stopped, steps)."""
    n_cols, w, x = len(sc.heights), sc.depth / 2, sc.dx
    cells = [geometry.convex_polyhedron.box([-(n + 1.0) * x, -w, -0.5 * x], [-(n + 0.0) * x, w, sc.base(n)])
             for n in range(n_cols)]  # the steps
    cells += [geometry.convex_polyhedron.box([-(n + 1.0) * x, -w, sc.base(n)], [-(n + 0.0) * x, w, sc.top(n)])
              for n in range(n_cols)]  # the columns, each on its step
    tess = geometry.separate_blocks(cells)
    joint = law.dry_joint(sc.k, sc.k, law.friction_angle.from_degrees(phi_deg))
    options = tessera.solver_options()
    options.damping_gamma = sc.damping
    s = tessera.instances.rigid_dry_damped_solver(tess, geometry.zone_blocks(tess), tessera.blocks.rigid.params(sc.density),
                                                  tessera.contact.detected_dry_joints(joint, tolerance=0.01 * x),
                                                  options=options)
    s.fix_blocks(s.blocks_on_plane(2, -0.5 * x, 1e-9))
    gravity = [G * math.sin(sc.psi_deg * DEG), G * 0.0, G * -math.cos(sc.psi_deg * DEG)]

    def ramp(m):  # gravity grows linearly over sc.ramp s
        f = min(1.0, m.time() / sc.ramp if sc.ramp > 0 else 1.0)
        s.set_gravity([f * gravity[0], f * gravity[1], f * gravity[2]])
        return False

    def largest(m):  # the largest column displacement (m), as the C++ quantity sums it
        u = 0.0
        for b in range(n_cols, 2 * n_cols):
            d = m.block_displacement(b)
            u = max(u, math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]))
        return u

    moved = quantity.of(largest, "largest column displacement (m)")
    ramp(s)
    r = s.run_until(stop.when(ramp, "gravity ramp", every=1)  # after every step, as the C++ observer
                    | stop.when_beyond(moved, 0.02 * x)  # unstable: a column moved 2 mm
                    | stop.when_settled(moved, 1e-5 * x, stop.over_time(0.1))  # stable
                    | stop.after_time(duration), int(duration / s.dt()) + 2)
    return largest(s), r.reason, r.steps


def support_force(sc, phi_deg):
    """Goodman-Bray limit equilibrium from the top column down: (P_0 at the toe N, modes toe first)."""
    t, ps, pc = math.tan(phi_deg * DEG), math.sin(sc.psi_deg * DEG), math.cos(sc.psi_deg * DEG)
    n_cols = len(sc.heights)
    modes, p = ["?"] * n_cols, 0.0
    for n in reversed(range(n_cols)):
        y = sc.heights[n] * sc.dx
        weight = sc.density * G * sc.depth * sc.dx * y
        m_arm = (min(sc.top(n), sc.top(n + 1)) if n + 1 < n_cols else sc.top(n)) - sc.base(n)
        l_arm = (min(sc.top(n), sc.top(n - 1)) if n > 0 else sc.top(n)) - sc.base(n)
        topple = (p * (m_arm - sc.dx * t) + weight / 2 * (y * ps - sc.dx * pc)) / l_arm
        slide = p - weight * (pc * t - ps) / (1 - t * t)
        modes[n] = "s" if topple <= 0 and slide <= 0 else ("T" if topple > slide else "S")
        p = max(0.0, topple, slide)
    return p, "".join(modes)


def main(argv=None):
    a = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    a.add_argument("--out", default="results/python_toppling")
    a.add_argument("--quick", action="store_true", help="5 bisections, 0.7 s per run")
    args = a.parse_args(argv)
    sc = scene()
    iterations, duration = (5, 0.7) if args.quick else (8, 1.0)
    lo, reference = sc.psi_deg, 44.9  # the closed form's critical friction, bisected to 1e-15 deg
    for _ in range(60):
        mid = (lo + reference) / 2
        if support_force(sc, mid)[0] > 0:
            lo = mid
        else:
            reference = mid
    with tessera.run_record(args.out, "toppling.py", sys.argv[1:] if argv is None else argv) as record:
        s_lo, s_hi, steps = sc.psi_deg, 44.9, 0
        for _ in range(iterations):
            mid = (s_lo + s_hi) / 2
            moved, _, n = simulate(sc, mid, duration)
            steps += n
            if moved > 0.02 * sc.dx:
                s_lo = mid
            else:
                s_hi = mid
        measured = (s_lo + s_hi) / 2
        phis = [sc.psi_deg - 5, reference + 5]
        if not args.quick:
            phis[1:1] = [(sc.psi_deg + reference) / 2, reference - 1, reference + 1]
        rows = []
        for phi in phis:
            moved, reason, n = simulate(sc, phi, duration)
            steps += n
            p0, modes = support_force(sc, phi)
            rows.append((phi, p0, moved))
            print("  phi %5.2f deg: limit equilibrium %s (s stable, T toppling, S sliding; toe first), P_0 %.4g N; "
                  "simulated: %s" % (phi, modes, p0, reason))
        with open(record.file("regions.csv"), "w") as f:
            f.write("phi_deg,P0_N,max_displacement_m\n")
            f.writelines(",".join("%.17g" % v for v in row) + "\n" for row in rows)
        error = (measured - reference) / reference
        with open(record.file("summary.json"), "w") as f:
            json.dump({"example": "toppling.py", "quick": args.quick, "critical_friction_deg": measured,
                       "critical_friction_bracket_deg": [s_lo, s_hi], "reference_critical_friction_deg": reference,
                       "error_rel": error, "steps": steps}, f, indent=2)
    print("toppling.py: critical friction %.3f deg simulated (%.3f..%.3f), %.3f deg limit equilibrium, error %+.2f %%; "
          "%d steps" % (measured, s_lo, s_hi, reference, 100 * error, steps))
    return 0 if abs(error) < 0.05 else 1


if __name__ == "__main__":
    sys.exit(main())
