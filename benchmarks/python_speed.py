#!/usr/bin/env python3
"""A Python-driven run against the same run in C++ (issue #66, docs/performance.md): CPU time,
one thread (OMP_NUM_THREADS=1), the two alternated, medians of N pairs. On the shared machine the
CPU time is the figure (wall time also holds the time a process waited for a core).

    /usr/bin/python3 benchmarks/python_speed.py build/release [N]

- arch, in this process: tessera._arch_reference() (the README's arch, tests/consumer/arch.cpp's
  scene and stop conditions compiled into the module) against examples/python/arch.py's
  run_arch with its Python recorder every 200 steps; time.process_time() around each.
- prism, in this process: tessera._tension_reference() (python/tension_reference.hpp compiled
  into the module) against examples/python/direct_tension.py's tension_run(...).run(), the same
  work (a Python callable every step over the 2 980 ramp steps, every 100 steps over the other
  18 820); and the cost of that every-step callable alone.
- prism, two processes: the program tessera_python_tension_cpp (the same header) against the
  script; each prints run_cpu_s, the CPU time of its scene and run; the process's whole CPU time
  (with the interpreter's start and the imports) is given too. Checks that each pair wrote the
  same curve.csv.
- Brazilian disc, two processes: examples/brazilian --quick --threads 1 against
  examples/python/brazilian.py --quick (a Python callable every 40 steps that copies the
  sub-contacts' state for the split check); the whole processes' CPU time; the same curve.csv.
Prints the medians and the ratios Python / C++.
"""
import filecmp
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def process(cmd, cwd, env):
    """(run_cpu_s printed by the process, the process's CPU s)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, cwd=cwd, env=env, check=True, capture_output=True, text=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = float(out.split("run_cpu_s ")[1].split()[0])
    return run, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def arch(pairs):
    import tessera  # noqa: F401  (the package of PYTHONPATH)
    sys.path.insert(0, str(ROOT / "examples" / "python"))
    import arch as script

    cpp, py = [], []
    for _ in range(pairs):
        t = time.process_time()
        tessera._arch_reference()
        cpp.append(time.process_time() - t)
        rows = []
        t = time.process_time()
        script.run_arch(lambda s: rows.append(s.step_count()))
        py.append(time.process_time() - t)
    c, p = statistics.median(cpp), statistics.median(py)
    print("arch (in process): C++ %.4f s, Python %.4f s (%d recorder calls), Python / C++ = %.3f"
          % (c, p, len(rows), p / c))


def prism_in_process(pairs):
    import tessera
    import direct_tension as script

    cpp, py = [], []
    for _ in range(pairs):
        t = time.process_time()
        tessera._tension_reference()
        cpp.append(time.process_time() - t)
        t = time.process_time()
        script.tension_run().run()
        py.append(time.process_time() - t)
    c, p = statistics.median(cpp), statistics.median(py)
    print("prism (in process): C++ %.3f s, Python %.3f s, Python / C++ = %.3f" % (c, p, p / c))


def ramp_callback_cost(pairs):
    """CPU per step of a Python callable every step (the prism's ramp: evaluate(), which updates
    the top's velocity), against the same 2 980 steps with none, on two prisms built alike."""
    import tessera
    import direct_tension as script

    extra, step = [], []
    for _ in range(pairs):
        a, b = script.tension_run(), script.tension_run()
        t = time.process_time()
        a.s.run_until(tessera.stop.after_steps(2980))
        plain = time.process_time() - t
        t = time.process_time()
        b.s.run_until(tessera.stop.when(lambda sv: b.evaluate(sv) or sv.step_count() >= 2980, "ramp", every=1))
        extra.append((time.process_time() - t - plain) / 2980)
        step.append(plain / 2980)
    print("a Python callable every step: %.1f us a step, against %.0f us for the step (the prism's first 2 980)"
          % (statistics.median(extra) * 1e6, statistics.median(step) * 1e6))


def prism(build, pairs):
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=str(build / "python"))
    cpp_cmd = [str(build / "python" / "tessera_python_tension_cpp"), "--threads", "1"]
    py_cmd = ["/usr/bin/python3", str(ROOT / "examples/python/direct_tension.py"), "--threads", "1", "--out", "."]
    times = {"C++": [], "Python": []}
    with tempfile.TemporaryDirectory() as tmp:
        dirs = {k: pathlib.Path(tmp) / k for k in times}
        for d in dirs.values():
            d.mkdir()
        for _ in range(pairs):
            times["C++"].append(process(cpp_cmd, dirs["C++"], env))
            times["Python"].append(process(py_cmd, dirs["Python"], env))
        same = filecmp.cmp(dirs["C++"] / "curve.csv", dirs["Python"] / "curve.csv", shallow=False)
    cr, pr = (statistics.median(t[0] for t in times[k]) for k in times)
    cp, pp = (statistics.median(t[1] for t in times[k]) for k in times)
    print("prism run: C++ %.3f s, Python %.3f s, Python / C++ = %.3f; whole process: C++ %.3f s, Python %.3f s, "
          "Python / C++ = %.3f; curve.csv %s" % (cr, pr, pr / cr, cp, pp, pp / cp,
                                                 "the same bits" if same else "DIFFERS"))


def cpu_of(cmd, cwd, env):
    """The process's CPU s (user + system)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, cwd=cwd, env=env, check=True, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def brazilian(build, pairs):
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=str(build / "python"))
    times = {"C++": [], "Python": []}
    with tempfile.TemporaryDirectory() as tmp:
        dirs = {k: pathlib.Path(tmp) / k for k in times}
        cmds = {"C++": [str(build / "examples" / "brazilian"), "--quick", "--threads", "1", "--out", str(dirs["C++"])],
                "Python": ["/usr/bin/python3", str(ROOT / "examples/python/brazilian.py"), "--quick", "--threads", "1",
                           "--out", str(dirs["Python"])]}
        for _ in range(pairs):
            for k in times:
                times[k].append(cpu_of(cmds[k], tmp, env))
        same = filecmp.cmp(dirs["C++"] / "curve.csv", dirs["Python"] / "curve.csv", shallow=False)
    c, p = (statistics.median(times[k]) for k in times)
    print("brazilian --quick, whole processes: C++ %.3f s, Python %.3f s, Python / C++ = %.3f; curve.csv %s"
          % (c, p, p / c, "the same bits" if same else "DIFFERS"))


def main():
    build = pathlib.Path(sys.argv[1]).resolve()
    pairs = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    os.environ["OMP_NUM_THREADS"] = "1"  # before the module starts OpenMP
    sys.path.insert(0, str(build / "python"))
    print("medians of %d alternated pairs, CPU time, one thread" % pairs)
    arch(pairs)
    prism_in_process(pairs)
    ramp_callback_cost(pairs)
    prism(build, pairs)
    if (build / "examples" / "brazilian").exists():
        brazilian(build, pairs)


if __name__ == "__main__":
    main()
