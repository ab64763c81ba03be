#!/usr/bin/env bash
# A long run shows that it is alive from its first minute: runs a driver into OUT with stderr
# to a file (not a terminal, as under a batch system), and checks that run.json says "running"
# while the process still runs, that stderr gets a progress line, and that an interrupt then
# leaves run.json "interrupted" and no summary.json.
#   check_alive.sh EXE OUT [driver args...]   (a run long enough not to end by itself first)
set -u
exe=$1 out=$2
shift 2
rm -rf "$out" "$out.stderr"
mkdir -p "$(dirname "$out")"
"$exe" "$@" --out "$out" > /dev/null 2> "$out.stderr" &
pid=$!
fail() {
  echo "check_alive: $*"
  kill -INT "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  cat "$out/run.json" 2> /dev/null
  cat "$out.stderr"
  exit 1
}
# Inputs, scene and checks take seconds alone; allow minutes on a busy machine.
running=0
for _ in $(seq 1 3000); do
  kill -0 "$pid" 2> /dev/null || fail "the driver ended before run.json said running"
  if grep -q '"status": "running"' "$out/run.json" 2> /dev/null; then
    running=1
    break
  fi
  sleep 0.1
done
((running)) || fail "no run.json saying running after 300 s"
lines=0
for _ in $(seq 1 1200); do
  kill -0 "$pid" 2> /dev/null || fail "the driver ended before it printed progress"
  lines=$(grep -c '%' "$out.stderr")
  ((lines >= 1)) && break
  sleep 0.1
done
((lines >= 1)) || fail "no progress line on a non-terminal stderr within 120 s of run.json"
grep -q $'\r' "$out.stderr" && fail "progress to a non-terminal stderr uses carriage returns"
kill -INT "$pid"
wait "$pid"
rc=$?
[[ $rc -ne 0 ]] || fail "the interrupted run exited 0"
grep -q '"status": "interrupted"' "$out/run.json" || fail "run.json does not say interrupted"
[[ ! -e "$out/summary.json" ]] || fail "summary.json exists after an interrupt"
echo "alive: run.json running, progress: $(head -n 1 "$out.stderr")"
