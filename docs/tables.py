#!/usr/bin/env python3
"""The opening tables of docs/validation.md and docs/performance.md, and a check of the docs' links.

Each page opens with one table (figure, tessera, reference, error, run time, command) between the
markers <!-- table:begin --> and <!-- table:end -->. The rows are the data below: for a row that a
driver's summary.json gives, the summary's keys it must match and the fields it reads; for a row
that no summary holds (benchmarks, work-precision figures, memory), its cells as measured.

  python3 docs/tables.py --results results/ --write   rewrite the tables: every row whose summary is
                                                      found under results/ (any depth) is filled
                                                      from it; the others keep the page's cells
                                                      (or the row's seed cells if the page has none)
  python3 docs/tables.py --check                      the tables have the rows of the data, in order,
                                                      with their figure, reference and command, and
                                                      every relative link in README.md, docs/*.md and
                                                      docs/studies/*.md reaches a file and heading;
                                                      validation.md and performance.md are at most
                                                      500 lines; README.md and docs/*.md carry no date
  python3 docs/tables.py --check --results results/   also: the rows found under results/ read as
                                                      the page says

Exit status: 0 when the pages are as the data says, 1 otherwise (each difference is printed).
Standard library only.
"""
import argparse
import json
import pathlib
import re
import sys
import unicodedata

ROOT = pathlib.Path(__file__).resolve().parent.parent
BEGIN, END = "<!-- table:begin -->", "<!-- table:end -->"
HEADER = ["figure", "tessera", "reference", "error", "run time", "command"]

NONEMPTY = object()  # a match value: the key is present and not empty (e.g. --params FILE)


def kn(v):
    return f"{v / 1e3:.2f} kN"


def pct(v, digits=1):
    return f"{v * 100:+.{digits}f} %".replace("-", "−")


def seconds(v):
    return f"{v:.2f} s" if v < 1 else f"{v:.1f} s" if v < 100 else f"{v:,.0f} s".replace(",", " ")


def count(v):
    return f"{int(v):,}".replace(",", " ")


def sci(v):
    if v == 0:
        return "0"
    s = f"{v:+.1e}"
    return ("−" + s[1:]) if s[0] == "-" else s


class Row:
    """One row. match: summary keys and values that pick its run (None: no summary holds it).
    fields: the summary fields read, in order; value(*fields) -> the tessera cell; error(*fields)
    -> the error cell; runtime: True to read runtime_s and threads. seed: the cells as measured
    (tessera, error, run time), used where neither a summary nor the page has them."""

    def __init__(self, figure, reference, command, seed, match=None, fields=(), value=None, error=None,
                 runtime=False):
        self.figure, self.reference, self.command, self.seed = figure, reference, command, seed
        self.match, self.fields, self.value, self.error, self.runtime = match, fields, value, error, runtime

    def fill(self, s):
        """The (tessera, error, run time) cells from summary s."""
        got = [s[f] for f in self.fields]
        t = self.value(*got)
        e = self.error(*got) if self.error else ""
        r = f"{seconds(s['runtime_s'])} ({s['threads']} thread{'s' if s['threads'] != 1 else ''})" if self.runtime else ""
        return t, e, r


def steps_faster_than(reference_s, digits=0):
    """A run's steps as its value and its speed against a reference time (s) as its error."""
    return dict(fields=("steps", "runtime_s"), value=lambda n, t: count(n),
                error=lambda n, t: f"{reference_s / t:.{digits}f}× faster", runtime=True)


def verified(value, error=sci):
    """verification's measured figure (formatted by value) and its relative error."""
    return dict(fields=("measured", "error_rel"), value=lambda m, e: value(m), error=lambda m, e: error(e), runtime=True)


TIE = {"example": "rc_tie", "blocks": 100, "seed": 1, "quick": False, "params": "", "scheme": "explicit",
       "rigid": False, "bare": False, "cohesion": "decoupled", "slip_breaks_tension": False, "softening": "power",
       "xi": 4, "elements": 96, "c_bond_N_per_m": 1e9, "rate_m_per_s": 0.005, "min_rate_factor": 1}
PRISM = {"example": "direct_tension", "blocks": 100, "seed": 1, "seeds": 1, "quick": False, "params": "",
         "scheme": "explicit", "rigid": False, "cohesion": "decoupled", "slip_breaks_tension": False}
BEAM = {"example": "rc_beam", "seed": 1, "quick": False, "parameters": "verbatim", "plates": "contact",
        "span": "half", "compression": "plastic", "cohesion": "decoupled", "slip_breaks_tension": False,
        "steel_yield_Pa": 440e6, "scheme": "explicit"}
VERIFY = {"example": "verification", "quick": False}
F_T = 2.15e6

VALIDATION = [
    Row("RC tie, yield plateau", "f_y A = 20.11 kN", "`rc_tie --no-vtk --threads 2`",
        ("20.81 kN", "+3.49 %", "35.2 s (2 threads)"), {**TIE, "threads": 2},
        ("yield_force_N", "yield_force_error_rel"), lambda f, e: kn(f), lambda f, e: pct(e, 2), True),
    Row("RC tie, initial stiffness", "85.5 kN/mm (shear lag)", "the same run",
        ("83.2 kN/mm", "−2.7 %", ""), {**TIE, "threads": 2},
        ("initial_stiffness_N_per_m", "initial_stiffness_shear_lag_error_rel"),
        lambda k, e: f"{k / 1e6:.1f} kN/mm", lambda k, e: pct(e)),
    Row("RC tie, first cracking", "N_cr = 10.6 kN (hand)", "the same run",
        ("13.07 kN", "+23.6 %", ""), {**TIE, "threads": 2},
        ("first_crack_force_N", "first_crack_error_rel"), lambda f, e: kn(f), lambda f, e: pct(e)),
    Row("RC tie, load drops / crack sites", "3 cracks (study Fig. 7)", "the same run",
        ("5 / 3", "", ""), {**TIE, "threads": 2}, ("load_drops", "crack_sites"), lambda d, c: f"{d} / {c}"),
    Row("RC tie, seeds 1–5: default (1 µs, 5 mm/s) against converged (1 µs, 2.5 mm/s)",
        "seed band of the curve 4.7 %", "`work_precision_figures --scene tie --threads 2`",
        ("first drop +1.67 ± 0.09 %, yield +1.00 ± 0.99 %, K0 +0.08 ± 0.07 %", "mean curve 2.08 %",
         "31.1 s against 78.5 s (2 threads, a run)")),
    Row("prism, peak stress", "f_T = 2.15 MPa", "`direct_tension --threads 1 --blocks 100`",
        ("2.376 MPa", "+10.5 %", "26.3 s (1 thread)"), {**PRISM, "threads": 1},
        ("peak_stress_Pa", "peak_error_rel"), lambda p, e: f"{p / 1e6:.3f} MPa", lambda p, e: pct(e), True),
    Row("prism, initial modulus", "E = 28 GPa", "the same run", ("28.8 GPa", "+2.7 %", ""),
        {**PRISM, "threads": 1}, ("initial_modulus_Pa", "initial_modulus_error_rel"),
        lambda m, e: f"{m / 1e9:.1f} GPa", lambda m, e: pct(e)),
    Row("prism, tension dissipated to separation", "G_f × crack area", "the same run",
        ("1.72 G_f × crack area", "+72 %", ""), {**PRISM, "threads": 1}, ("fracture_energy_error_rel",),
        lambda e: f"{1 + e:.2f} G_f × crack area", lambda e: pct(e, 0)),
    Row("prism, seeds 1–5: default (2 nm) against converged (1 nm)", "seed band of the curve 5.6 %",
        "`work_precision_figures --scene prism --threads 2`",
        ("peak +0.18 ± 0.24 %, E0 −1.07 ± 1.10 %", "mean curve 2.53 %", "20.8 s against 94.7 s (2 threads, a run)")),
]
for blocks, seed_cells in ((100, ("2.095 MPa", "−2.5 %", "11.3 s (2 threads)")),
                           (250, ("2.100 MPa", "−2.3 %", "34.1 s (2 threads)")),
                           (500, ("2.132 MPa", "−0.8 %", "81.2 s (2 threads)"))):
    VALIDATION.append(Row(
        f"prism, {blocks} blocks, calibrated, mean peak of unseen seeds 7–9", "f_T = 2.15 MPa",
        f"`calibrate --blocks 100,250,500 --seeds 6 --threads 2`, then `direct_tension --blocks {blocks} "
        "--seeds 3 --seed 7 --max-displacement 1.2e-4 --params calibrated.json --threads 2`",
        seed_cells, {**PRISM, "blocks": blocks, "seed": 7, "seeds": 3, "params": NONEMPTY},
        ("peak_stress_mean_Pa",), lambda p: f"{p / 1e6:.3f} MPa", lambda p: pct(p / F_T - 1), True))
VALIDATION += [
    Row("RC beam, 250 blocks, yield", "A_s f_y z = 52.96 kN", "`rc_beam --blocks 250 --seed 1 --no-vtk --threads 2`",
        ("54.74 kN", "+3.4 %", "1 184 s (2 threads)"), {**BEAM, "blocks": 250},
        ("yield_load_N", "yield_error_rel"), lambda f, e: kn(f), lambda f, e: pct(e), True),
    Row("RC beam, 250 blocks, initial stiffness", "44.9 kN/mm (E = 25 GPa, bending + shear)", "the same run",
        ("37.0 kN/mm", "−17.6 %", ""), {**BEAM, "blocks": 250},
        ("initial_stiffness_N_per_m", "initial_stiffness_error_rel"),
        lambda k, e: f"{k / 1e6:.1f} kN/mm", lambda k, e: pct(e)),
    Row("RC beam, 250 blocks, flexural crack spacing", "90 mm (study)", "the same run",
        ("142 mm", "+58 %", ""), {**BEAM, "blocks": 250}, ("mean_crack_spacing_m",),
        lambda s: f"{s * 1e3:.0f} mm", lambda s: pct(s / 0.09 - 1, 0)),
    Row("RC beam, failure mode", "diagonal tension (study)", "the same run",
        ("flexure", "not reproduced", ""), {**BEAM, "blocks": 250}, ("failure_mode",), lambda m: m,
        lambda m: "not reproduced" if m != "diagonal_tension" else "reproduced"),
    Row("RC beam, 500 blocks, yield", "A_s f_y z = 52.96 kN", "`rc_beam --blocks 500 --seed 2 --no-vtk --threads 2`",
        ("54.98 kN", "+3.8 %", "2 242 s (2 threads)"), {**BEAM, "blocks": 500, "seed": 2},
        ("yield_load_N", "yield_error_rel"), lambda f, e: kn(f), lambda f, e: pct(e), True),
    Row("rigid block sliding on an incline (40°, φ = 30°), acceleration", "g (sin θ − cos θ tan φ)",
        "`verification --threads 1 --case incline --angle-deg 40 --friction-deg 30`",
        ("1.96702 m/s²", "−1.3e-08", "0.12 s (1 thread)"),
        {**VERIFY, "case": "incline", "angle_deg": 40, "friction_deg": 30, "block_model": "rigid"},
        **verified(lambda m: f"{m:.5f} m/s²")),
    Row("bonded face (c_0 = 3 kPa), failure force", "c_0 A = 750 N",
        "`verification --threads 1 --case bond --angle-deg 40 --friction-deg 30`",
        ("749.93 N", "−9.5e-05", "0.12 s (1 thread)"),
        {**VERIFY, "case": "bond", "angle_deg": 40, "friction_deg": 30},
        **verified(lambda m: f"{m:.2f} N")),
    Row("stack of 5 blocks, base reaction", "total weight 20 601 N", "`verification --threads 1 --case stack --blocks 5`",
        ("20 601 N", "+1.8e-16", "0.28 s (1 thread)"), {**VERIFY, "case": "stack", "blocks": 5, "block_model": "rigid"},
        **verified(lambda m: f"{count(round(m))} N")),
    Row("deformable block sliding on an incline (40°, φ = 30°)", "g (sin θ − cos θ tan φ)",
        "`verification --deformable --threads 1 --case incline --angle-deg 40 --friction-deg 30`",
        ("1.97045 m/s²", "+1.7e-03", "6.0 s (1 thread)"),
        {**VERIFY, "case": "incline", "angle_deg": 40, "friction_deg": 30, "block_model": "deformable"},
        **verified(lambda m: f"{m:.5f} m/s²")),
    Row("cracked prism reclosed, stiffness in compression", "intact prism 4.7548e10 Pa/m",
        "`verification --threads 2 --case reclose`", ("4.7742e10 Pa/m", "+0.41 %", "4.5 s (2 threads)"),
        {**VERIFY, "case": "reclose"}, ("measured", "error_rel"), lambda m, e: f"{m:.4e} Pa/m",
        lambda m, e: pct(e, 2), True),
    Row("toppling row (guide), critical friction angle", "34.026° (Goodman & Bray)", "`toppling --threads 1`",
        ("33.569°", "−1.34 %", "3 s (1 thread)"), {"example": "toppling", "quick": False},
        ("critical_friction_deg", "error_rel"), lambda p, e: f"{p:.3f}°", lambda p, e: pct(e, 2), True),
    Row("rocking block (guide), coefficient of restitution", "0.9118 (Housner)", "`rocking --threads 1`",
        ("0.9544", "+4.68 %", "0.4 s (1 thread)"), {"example": "rocking", "quick": False},
        ("restitution", "error_rel"), lambda r, e: f"{r:.4f}", lambda r, e: pct(e, 2), True),
    Row("rocking block (guide), time to first impact", "0.3118 s (Housner)", "the same run",
        ("0.3123 s", "+0.18 %", ""), {"example": "rocking", "quick": False},
        ("first_impact_s", "first_impact_error_rel"), lambda t, e: f"{t:.4f} s", lambda t, e: pct(e, 2)),
    Row("Brazilian disc, 38 blocks (guide), f_sp / f_T", "1.11 (EC2)", "`brazilian --threads 1 --seed 1`",
        ("2.19", "2.0×", "4.3 s (1 thread)"), {"example": "brazilian", "quick": False, "seed": 1, "blocks": 38},
        ("f_sp_over_f_T",), lambda r: f"{r:.2f}", lambda r: f"{r / 1.11:.1f}×", True),
    Row("Brazilian disc, 150 blocks, f_sp / f_T at the diametral crack", "1.11 (EC2; 1.0-1.4 accepted)",
        "`brazilian --threads 1 --blocks 150 --seed 2`",
        ("1.26", "1.1×", "38 s (1 thread)"), {"example": "brazilian", "quick": False, "seed": 2, "blocks": 150},
        ("f_sp_crack_opening_over_f_T",), lambda r: f"{r:.2f}", lambda r: f"{r / 1.11:.1f}×", True),
    Row("compression, 150 × 300 mm cylinder of the beam's concrete (61 blocks), f_c, frictionless ends",
        "35 MPa (the beam's f_c)", "`compression --threads 1 --no-vtk`",
        ("17.38 MPa at strain 0.96e-3", "−50.3 %", "225 s (1 thread)"),
        {"example": "compression", "quick": False, "seed": 1, "ends": "frictionless", "confinement_Pa": 0,
         "phi_0_deg": 35, "cap_Pa": 35e6, "c_0_Pa": 5e6},
        ("f_c_Pa", "peak_strain"), lambda f, e: f"{f * 1e-6:.2f} MPa at strain {e * 1e3:.2f}e-3",
        lambda f, e: pct(f / 35e6 - 1, 1), True),
]

PERFORMANCE = [
    Row("zone update, 100-block prism, per zone-step (portable build)", "multiply-add ceiling 11.7 ns (260 flops at 22.3 GFLOP/s)",
        "`taskset -c 1 build/bench-portable/benchmarks/bench_kernels --benchmark_repetitions=3`",
        ("18.7 ns (`-march=native`: 15.9 ns)", "1.6× the ceiling", "")),
    Row("contact law over packs, per sub-contact-step (portable build)", "",
        "`taskset -c 1 build/bench-portable/benchmarks/bench_contacts --benchmark_filter=threads:1`",
        ("18.2 ns (`-march=native`: 13.4 ns)", "", "")),
    Row("100-block RC tie, one thread, per sub-contact-step / per zone-step", "", "`rc_tie --no-vtk --threads 1`",
        ("21.2–22.1 ns / 21.6–22.3 ns", "", "39.5 s (1 thread)"), {**TIE, "threads": 1},
        ("ns_per_subcontact_step", "ns_per_zone_step"), lambda c, z: f"{c:.1f} ns / {z:.1f} ns", None, True),
    Row("100-block RC tie to 25 % past yield, steps", "3DEC: 20 min (study Table 2)", "`rc_tie --no-vtk --threads 2`",
        ("239 350", "34× faster", "35.2 s (2 threads)"), {**TIE, "threads": 2}, **steps_faster_than(1200)),
    Row("500-block RC tie, steps", "3DEC: 130 min", "`rc_tie --blocks 500 --no-vtk --threads 2`",
        ("603 375", "18× faster", "439.5 s (2 threads)"), {**TIE, "blocks": 500, "threads": 2},
        **steps_faster_than(7800)),
    Row("100-block prism to separation, steps", "", "`direct_tension --threads 1 --blocks 100`",
        ("202 500", "", "26.3 s (1 thread)"), {**PRISM, "threads": 1}, ("steps",), lambda n: count(n), None, True),
    Row("the same on 2 threads", "one thread: 26.3 s", "`direct_tension --threads 2 --blocks 100`",
        ("202 500", "1.65× faster", "16.0 s (2 threads)"), {**PRISM, "threads": 2}, **steps_faster_than(26.3, 2)),
    Row("250-block RC beam to 6 mm, steps", "3DEC: 420 min", "`rc_beam --blocks 250 --seed 1 --no-vtk --threads 2`",
        ("1 119 800", "21× faster", "1 184 s (2 threads)"), {**BEAM, "blocks": 250, "threads": 2},
        **steps_faster_than(25200)),
    Row("500-block RC beam to 6 mm, steps", "3DEC: 990 min", "`rc_beam --blocks 500 --seed 3 --no-vtk --threads 2`",
        ("1 083 700", "38× faster", "1 561 s (2 threads)"), {**BEAM, "blocks": 500, "seed": 3, "threads": 2},
        **steps_faster_than(59400)),
    Row("contact detection pass, 1 000 blocks", "", "`build/bench/benchmarks/bench_detection --benchmark_repetitions=3`",
        ("91.8 ms (1 thread), 47.7 ms (2 threads)", "", "")),
    Row("rubble: 1 000 blocks dropped, 1 s, share of the run in rebuilds",
        "full pass (c8ed806) run beside it: 79.5 %, 285.4 s (3 471 rebuilds, exchange −393 J against −363 J)",
        "`rubble --threads 2 --no-vtk`", ("26 % (6 410 rebuilds, 38 885 steps)", "run x0.25", "72.2 s (2 threads)"),
        {"example": "rubble", "quick": False, "blocks": 1000, "threads": 2, "duration_s": 1},
        ("rebuild_s", "runtime_s", "rebuilds", "steps"),
        lambda b, t, r, n: f"{b / t * 100:.0f} % ({count(r)} rebuilds, {count(n)} steps)", None, True),
    Row("prism in direct tension, cost per contact-step, all-in", "YADE CPM: 1 130 ns per interaction-step",
        "`bash benchmarks/side_by_side.sh build/release 0.006`", ("104.8 ns per sub-contact-step", "10.8× less", "")),
    Row("10 000-block RC tie, resident memory", "", "`/usr/bin/time -f %M rc_tie --blocks 10000 --elements 192 "
        "--dt 1e-6 --max-elongation 3e-4 --threads 2 --no-vtk`", ("425 MB, 42 kB a block", "", "1 036 s (2 threads)")),
    Row("500-block prism split over 2 MPI ranks, ms a step", "one process, one thread: 4.22 ms",
        "`mpirun -np 2 --oversubscribe --mca mpi_yield_when_idle 1 direct_tension --blocks 500 "
        "--step-displacement 5e-9 --max-displacement 1.5e-5 --threads 1`", ("2.23 ms", "1.89× faster", "")),
    Row("10 000-block prism, 2 ranks on local models, peak memory a rank", "one process: 381.7 MB",
        "`mpirun -np 2 split_storage --blocks 10000 --steps 300 --storage local`", ("206.6, 212.0 MB", "0.54–0.56×", "")),
    Row("100-block prism, elastic branch by the implicit solve", "explicit: 10 100 steps, 1.15–1.22 s CPU",
        "`implicit_prism --seed 1`", ("one factorisation, 0.053–0.058 s CPU", "20× faster", "")),
    Row("100-block prism to 80 µm (past its peak) by kinetic relaxation, steps", "explicit: 41 600 steps, 12.8–13.3 s",
        "`direct_tension --seed 1 --threads 1 --max-displacement 8e-5 --scheme relaxation`",
        ("8 457", "4.9× fewer", "2.9–3.5 s (1 thread)")),
    Row("compile the README's prism program header-only (tests/consumer/main.cpp), CPU and peak memory", "",
        "`REPEAT=3 benchmarks/compile_time.sh`", ("24.4 s, 1 043 MB (median of 3, quiet machine)", "", "")),
    Row("compile a guide rigid scene linking tessera::instances (benchmarks/compile_time/rigid_scene.cpp), CPU and peak memory",
        "before its members left the headers: 10.5 s, 593 MB", "`REPEAT=3 benchmarks/compile_time.sh`",
        ("5.6 s, 456 MB (median of 3, quiet machine)", "0.53× the time", "")),
    Row("compile the README's arch linking tessera::instances (tests/consumer/arch.cpp), CPU and peak memory",
        "before: 12.6 s, 735 MB", "`REPEAT=3 benchmarks/compile_time.sh`",
        ("8.6 s, 544 MB (median of 3, quiet machine)", "0.68× the time", "")),
]

PAGES = {"docs/validation.md": VALIDATION, "docs/performance.md": PERFORMANCE}


def cells_of_line(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def render(rows_cells):
    out = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    out += ["| " + " | ".join(c) + " |" for c in rows_cells]
    return out


def page_table(text):
    """The lines between the markers, or None."""
    if BEGIN not in text or END not in text:
        return None
    body = text.split(BEGIN, 1)[1].split(END, 1)[0]
    return [l for l in body.strip("\n").split("\n") if l.strip()]


def load_results(folder):
    found = []
    for p in sorted(pathlib.Path(folder).rglob("summary.json")):
        try:
            found.append((p, json.loads(p.read_text())))
        except (OSError, json.JSONDecodeError) as e:
            print(f"tables: skipping {p}: {e}", file=sys.stderr)
    return found


def matches(summary, match):
    for k, want in match.items():
        if k not in summary:
            return False
        got = summary[k]
        if want is NONEMPTY:
            if got in ("", None):
                return False
        elif isinstance(want, float) or isinstance(got, float):
            if not isinstance(got, (int, float)) or isinstance(got, bool) or abs(got - want) > 1e-9 * abs(want):
                return False
        elif got != want:
            return False
    return True


def summary_for(row, results):
    """The first summary that matches the row and holds its fields (a null figure, e.g. no yield,
    leaves the row as the page has it)."""
    if row.match is None:
        return None, None
    hits = [(p, s) for p, s in results if matches(s, row.match)
            and all(s.get(f) is not None for f in row.fields + (("runtime_s", "threads") if row.runtime else ()))]
    if len(hits) > 1:
        print(f"tables: {len(hits)} summaries match '{row.figure}', using the first: "
              + ", ".join(str(p) for p, _ in hits), file=sys.stderr)
    return hits[0] if hits else (None, None)


def cells_from_page(row, old):
    for c in old:
        if len(c) == len(HEADER) and c[0] == row.figure:
            return c[1], c[3], c[4]
    return None


def table_for(rows, results, old):
    """The table's lines; the cells of each row from its summary, else the page, else its seed."""
    out = []
    for row in rows:
        _, s = summary_for(row, results)
        if s is not None:
            t, e, r = row.fill(s)
        else:
            t, e, r = cells_from_page(row, old) or row.seed
        out.append([row.figure, t, row.reference, e, r, row.command])
    return render(out)


def slug(heading):
    """GitHub's anchor for a heading."""
    s = heading.strip().lower()
    s = "".join(ch for ch in s if ch in "-_ " or unicodedata.category(ch)[0] in "LN")
    return s.replace(" ", "-")


def prose_lines(path):
    """(line number, line) of a markdown file outside its ``` fences."""
    fence = False
    for n, line in enumerate(path.read_text().split("\n"), 1):
        if line.startswith("```"):
            fence = not fence
        if not fence:
            yield n, line


def anchors(path, cache={}):
    if path not in cache:
        seen, out = {}, set()
        for _, line in prose_lines(path):
            m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                a = slug(re.sub(r"[`*]|\[([^\]]*)\]\([^)]*\)", r"\1", m.group(1)))
                n = seen.get(a, 0)
                seen[a] = n + 1
                out.add(a if n == 0 else f"{a}-{n}")
        cache[path] = out
    return cache[path]


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def check_links():
    bad = []
    pages = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md")) + sorted((ROOT / "docs/studies").glob("*.md"))
    for page in pages:
        for n, line in prose_lines(page):
            for target in LINK.findall(re.sub(r"`[^`]*`", "", line)):
                if re.match(r"[a-z]+:", target):
                    continue
                file, _, anchor = target.partition("#")
                dest = (page.parent / file).resolve() if file else page
                if not dest.exists():
                    bad.append(f"{page.relative_to(ROOT)}:{n}: {target}: no such file")
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    bad.append(f"{page.relative_to(ROOT)}:{n}: {target}: no heading #{anchor} in {dest.relative_to(ROOT)}")
    return bad


DATE = re.compile(r"\b20[0-9]{2}-[0-9]{2}-[0-9]{2}\b")
HISTORY_EXEMPT: set = set()  # every reference page is held to it


def check_reference_pages():
    """The reference pages: validation.md and performance.md at most 500 lines; no date in
    README.md or docs/*.md (dated runs belong to docs/studies/)."""
    bad = [f"{page}: {n} lines, more than 500" for page in PAGES
           if (n := len((ROOT / page).read_text().rstrip("\n").split("\n"))) > 500]
    for path in [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md")):
        rel = str(path.relative_to(ROOT))
        if rel in HISTORY_EXEMPT:
            continue
        for n, line in prose_lines(path):
            if DATE.search(line):
                bad.append(f"{rel}:{n}: a date in a reference page (dated runs go to docs/studies/)")
    return bad


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", help="folder searched (any depth) for the drivers' summary.json")
    ap.add_argument("--write", action="store_true", help="rewrite the tables between the markers")
    ap.add_argument("--check", action="store_true", help="check the tables and the docs' links")
    a = ap.parse_args()
    if a.write == a.check:
        ap.error("give one of --write and --check")
    results = load_results(a.results) if a.results else []
    if a.results and not results:
        print(f"tables: no summary.json under {a.results}", file=sys.stderr)
    problems = []
    for page, rows in PAGES.items():
        path = ROOT / page
        text = path.read_text()
        old_lines = page_table(text)
        if old_lines is None:
            problems.append(f"{page}: no {BEGIN} ... {END} markers")
            continue
        old = [cells_of_line(l) for l in old_lines[2:]]
        if a.write:
            new = table_for(rows, results, old)
            head, rest = text.split(BEGIN, 1)
            path.write_text(head + BEGIN + "\n" + "\n".join(new) + "\n" + END + rest.split(END, 1)[1])
            filled = sum(1 for r in rows if summary_for(r, results)[1] is not None)
            print(f"tables: {page}: {len(rows)} rows, {filled} from summaries under {a.results}")
            continue
        if old_lines[:2] != render([])[:2]:
            problems.append(f"{page}: the table's header is not | {' | '.join(HEADER)} |")
        if len(old) != len(rows):
            problems.append(f"{page}: {len(old)} rows in the table, {len(rows)} in the data")
        for i, (row, c) in enumerate(zip(rows, old), 1):
            if len(c) != len(HEADER):
                problems.append(f"{page}: row {i} has {len(c)} cells")
                continue
            for col, want in ((0, row.figure), (2, row.reference), (5, row.command)):
                if c[col] != want:
                    problems.append(f"{page}: row {i}, {HEADER[col]}: '{c[col]}', the data says '{want}'")
            if not c[1]:
                problems.append(f"{page}: row {i} ({row.figure}) has no value")
            p, s = summary_for(row, results)
            if s is not None and (c[1], c[3], c[4]) != row.fill(s):
                problems.append(f"{page}: row {i} ({row.figure}) reads {c[1]} | {c[3]} | {c[4]}; {p} gives "
                                + " | ".join(row.fill(s)))
    if a.check:
        problems += check_links() + check_reference_pages()
    for p in problems:
        print(p)
    if a.check and not problems:
        print(f"tables: {len(PAGES)} tables as their data says; every relative link resolves; "
              "the reference pages are under 500 lines and undated")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
