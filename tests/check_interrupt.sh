#!/usr/bin/env bash
# A killed run leaves no file that looks finished (io/run_record.hpp): runs a driver into OUT,
# sends SIGINT once its run.json says "running", and checks that run.json then says
# "interrupted", that no summary.json and no temporary file is left, and that a rerun into the
# same directory removes the files the interrupted run listed (and only those).
#   check_interrupt.sh EXE OUT [driver args...]   (EXE: rc_tie, which has --no-vtk and --max-elongation)
set -u
exe=$1 out=$2
shift 2
rm -rf "$out"
"$exe" "$@" --out "$out" > /dev/null 2>&1 &
pid=$!
for _ in $(seq 1 600); do
  grep -q '"status": "running"' "$out/run.json" 2> /dev/null && break
  sleep 0.1
done
sleep 1
kill -INT "$pid"
wait "$pid"
rc=$?
fail() { echo "check_interrupt: $*"; ls -la "$out"; cat "$out/run.json" 2> /dev/null; exit 1; }
[[ $rc -ne 0 ]] || fail "the interrupted run exited 0"
grep -q '"status": "interrupted"' "$out/run.json" || fail "run.json does not say interrupted"
[[ ! -e "$out/summary.json" ]] || fail "summary.json exists after an interrupt"
compgen -G "$out/*.tmp.*" > /dev/null && fail "temporary files left behind"
listed=$(python3 -c "import json,sys; print(' '.join(json.load(open(sys.argv[1]))['files']))" "$out/run.json")
touch "$out/user_file.txt"
# A short rerun into the same directory (it writes no VTK) removes what the interrupted run listed.
"$exe" "$@" --no-vtk --max-elongation 1e-5 --out "$out" > /dev/null 2>&1 || fail "the rerun failed"
for f in $listed; do [[ ! -e "$out/$f" ]] || fail "the rerun left the earlier run's $f"; done
[[ -e "$out/user_file.txt" ]] || fail "the rerun removed a file it did not write"
grep -q '"status": "complete"' "$out/run.json" || fail "the rerun's run.json does not say complete"
echo "interrupted with exit $rc; listed and removed by the rerun: ${listed:-none}"
