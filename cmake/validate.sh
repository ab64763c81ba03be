#!/usr/bin/env bash
# Reruns the validation of tessera against the reference study (Pulatsu et al. 2020) and writes
# its tables: the prism and the tie with the study's parameters verbatim and with the calibrated
# contact strength (examples/calibrate), the calibration itself, the tie's sensitivity studies,
# the beam, and error against run time (benchmarks/work_precision_figures: prism and tie at
# several steps and rates on five seeds), each figure beside its reference and run time, stamped
# with the commit.
#
#   bash cmake/validate.sh [--quick] [--threads N] [--beam-seeds N] [--out DIR] [--resume]
#
#   --quick    the reduced scenes (100 blocks, one seed, the drivers' --quick): about 2 min; the
#              tables go to DIR/validation.md only (the figures of reduced runs are not the
#              validation)
#   full       about 2.1 h (5024 s measured at 23c75be with 2 threads, and 2633 s at 22896da
#              for the beam's calibration and its two calibrated runs added since: the beam's
#              five runs 74 min of it, the two calibrations 26 min, the work-precision runs
#              15 min) on this project's 2-core machine, plus about 15 min since the tie's
#              step went from 2 to 1 us (the sensitivity studies took 1296 s at 1 us on
#              2026-11-27; the progress line estimates the rest); the tables go to DIR/validation.md and replace the generated section of
#              docs/studies/validate_run.md (between its "validate.sh" markers), and
#              `python3 docs/tables.py --results DIR --write` refills the opening tables of
#              docs/validation.md and docs/performance.md from the runs' summary.json
#   --beam-seeds N  seeds 1..N of the 250- and 500-block beams (default 1; each further seed adds
#              about 30 min); the beam table gives each seed and the band
#   --threads  worker threads per run (default 0: the drivers' automatic choice, one per core that
#              other processes leave idle; OpenMP threads that share a busy core slow a run by
#              up to 100x, see docs/performance.md)
#   --out DIR  where every run writes (default results/validation)
#   --resume   skip a run whose run.json says "complete" (after an interrupted validation)
#
# Builds the drivers with the portable `release` preset first (the reference build:
# docs/performance.md "Reproducibility"), and work_precision_figures with `bench-portable` (the
# same flags, with the benchmark directory). Exit status: non-zero if a build or a run fails; the
# tables are written only when every run completed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
quick=0
threads=0
out="$root/results/validation"
resume=0
beam_seeds=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) quick=1 ;;
    --resume) resume=1 ;;
    --threads)
      [[ $# -ge 2 && "$2" =~ ^(0|[1-9][0-9]?)$ ]] || { echo "validate: --threads needs an integer in [0, 99], got '${2:-}'" >&2; exit 2; }
      threads="$2"; shift ;;
    --beam-seeds)
      [[ $# -ge 2 && "$2" =~ ^[1-9]$ ]] || { echo "validate: --beam-seeds needs an integer in [1, 9], got '${2:-}'" >&2; exit 2; }
      beam_seeds="$2"; shift ;;
    --out)
      [[ $# -ge 2 && -n "$2" ]] || { echo "validate: --out needs a directory" >&2; exit 2; }
      out="$2"; shift ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "validate: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

cmake --preset release > /dev/null
cmake --build --preset release --target direct_tension rc_tie calibrate rc_tie_sensitivity rc_beam > /dev/null
cmake --preset bench-portable > /dev/null
cmake --build --preset bench-portable --target work_precision_figures > /dev/null
bin="$root/build/release/examples"
wp="$root/build/bench-portable/benchmarks/work_precision_figures"
mkdir -p "$out"
cal="$out/calibrate/calibrated.json"
cal_beam="$out/calibrate_beam/calibrated.json"

# The runs: name, estimated seconds on this machine (2 threads), command. The estimates only
# drive the progress line.
names=(); estimates=(); commands=()
add() { names+=("$1"); estimates+=("$2"); shift 2; commands+=("$*"); }
if [[ $quick == 1 ]]; then
  blocks_list=(100)
  add prism_verbatim_100 5 "$bin/direct_tension --quick"
  add tie_verbatim 5 "$bin/rc_tie --quick --no-vtk"
  add calibrate 12 "$bin/calibrate --quick"
  add prism_calibrated_100 5 "$bin/direct_tension --quick --seed 2 --params $cal"
  add tie_calibrated 5 "$bin/rc_tie --quick --no-vtk --params $cal"
  add sensitivity 60 "$bin/rc_tie_sensitivity --quick"
  beam_list=(quick)
  add beam_quick 8 "$bin/rc_beam --quick --no-vtk"
  add calibrate_beam 5 "$bin/calibrate --quick --material beam"
  beam_list+=(quick_calibrated)
  add beam_quick_calibrated 8 "$bin/rc_beam --quick --no-vtk --params $cal_beam"
  add work_precision_prism 120 "$wp --scene prism --quick"
  add work_precision_tie 20 "$wp --scene tie --quick"
else
  blocks_list=(100 250 500)
  add prism_verbatim_100 15 "$bin/direct_tension --blocks 100 --seeds 3 --seed 1 --max-displacement 1.2e-4"
  add prism_verbatim_250 50 "$bin/direct_tension --blocks 250 --seeds 3 --seed 1 --max-displacement 1.2e-4"
  add prism_verbatim_500 110 "$bin/direct_tension --blocks 500 --seeds 3 --seed 1 --max-displacement 1.2e-4"
  add prism_separation 20 "$bin/direct_tension --blocks 100"
  add tie_verbatim 25 "$bin/rc_tie --no-vtk"
  add calibrate 830 "$bin/calibrate --blocks 100,250,500 --seeds 6"
  add prism_calibrated_100 13 "$bin/direct_tension --blocks 100 --seeds 3 --seed 7 --max-displacement 1.2e-4 --params $cal"
  add prism_calibrated_250 40 "$bin/direct_tension --blocks 250 --seeds 3 --seed 7 --max-displacement 1.2e-4 --params $cal"
  add prism_calibrated_500 95 "$bin/direct_tension --blocks 500 --seeds 3 --seed 7 --max-displacement 1.2e-4 --params $cal"
  add tie_calibrated 25 "$bin/rc_tie --no-vtk --params $cal"
  add sensitivity 1300 "$bin/rc_tie_sensitivity"
  beam_list=()
  for b in 250 500; do
    for ((k = 1; k <= beam_seeds; ++k)); do
      beam_list+=("${b}_s$k")
      add "beam_${b}_s$k" $([[ $b == 250 ]] && echo 730 || echo 1100) "$bin/rc_beam --blocks $b --seed $k --no-vtk"
    done
  done
  beam_list+=(250_elastic)
  add beam_250_elastic 700 "$bin/rc_beam --blocks 250 --seed 1 --compression elastic --no-vtk"
  add calibrate_beam 720 "$bin/calibrate --material beam --blocks 250,500 --seeds 3"
  for b in 250 500; do
    beam_list+=("${b}_calibrated")
    add "beam_${b}_calibrated" $([[ $b == 250 ]] && echo 780 || echo 1140) "$bin/rc_beam --blocks $b --seed 1 --no-vtk --params $cal_beam"
  done
  add work_precision_prism 1700 "$wp --scene prism"
  # Tie: 5 seeds x (11 explicit settings + kdr_10um_T1e-3); the converged setting alone took
  # 107 s a seed and the relaxation 105 s on 2 threads (2026-11-28), about 460 s a seed in all.
  add work_precision_tie 2300 "$wp --scene tie"
fi

# With --resume, a run whose run.json says "complete" is kept; the estimate counts the others.
kept=()
total=0
for i in "${!names[@]}"; do
  if [[ $resume == 1 ]] && grep -q '"status": "complete"' "$out/${names[$i]}/run.json" 2>/dev/null; then
    kept+=(1)
  else
    kept+=(0); total=$((total + estimates[i]))
  fi
done
start=$(date +%s)
done_estimate=0
for i in "${!names[@]}"; do
  name="${names[$i]}"
  dir="$out/$name"
  elapsed=$(( $(date +%s) - start ))
  left=$(( total - done_estimate ))
  printf 'validate: [%d/%d] %s (about %d s; %d s elapsed, about %d s left)\n' \
    $((i + 1)) ${#names[@]} "$name" "${estimates[$i]}" "$elapsed" "$left"
  if [[ ${kept[$i]} == 1 ]]; then
    echo "validate:   complete in an earlier run, kept"
    continue
  else
    # shellcheck disable=SC2086  # the command is a word list on purpose
    if ! ${commands[$i]} --threads "$threads" --out "$dir" > "$out/$name.log" 2>&1; then
      echo "validate: $name failed; its output is in $out/$name.log" >&2
      tail -5 "$out/$name.log" >&2
      exit 1
    fi
  fi
  done_estimate=$((done_estimate + estimates[i]))
done
runs_s=$(( $(date +%s) - start ))
echo "validate: all runs complete in $runs_s s"

# ---- the tables ----
# summary.json holds one key per line ("key": value,), so awk reads it without a JSON parser.
get() {  # get FILE KEY -> the value, or "null"
  awk -v k="\"$2\":" '$1 == k { v = $2; sub(/,$/, "", v); print v; found = 1; exit } END { if (!found) print "null" }' "$1"
}
pct() { awk -v x="$1" 'BEGIN { if (x == "null") print "—"; else printf "%+.1f %%", 100 * x }'; }
num() { awk -v x="$1" -v s="$2" -v f="$3" 'BEGIN { if (x == "null") print "—"; else printf f, x * s }'; }
# The commits the drivers were built at (run.json; one unless --resume mixed builds).
commit=$(for n in "${names[@]}"; do get "$out/$n/run.json" commit; done | tr -d '"' | sort -u | paste -sd, -)
report="$out/validation.md"
{
  echo "Generated by \`bash cmake/validate.sh$([[ $quick == 1 ]] && echo ' --quick')\` at commit $commit on $(date -u +%Y-%m-%d), $([[ $threads == 0 ]] && echo 'automatic threads' || echo "$threads threads"), portable \`release\` build; runs $runs_s s$([[ $resume == 1 ]] && echo ' (this invocation; --resume kept earlier runs)')."
  echo
  echo "**Prism in direct tension**: mean peak over the seeds against f_T = 2.15 MPa (range in brackets); verbatim = the study's parameters, calibrated = \`--params\` on seeds the fit did not use."
  echo
  echo "| blocks | parameters | seeds | mean peak | error | range | run time |"
  echo "|---|---|---|---|---|---|---|"
  for b in "${blocks_list[@]}"; do
    for kind in verbatim calibrated; do
      s="$out/prism_${kind}_$b/summary.json"
      mean=$(get "$s" peak_stress_mean_Pa); f_t=$(get "$s" f_T_Pa)
      err=$(awk -v m="$mean" -v f="$f_t" 'BEGIN { print m / f - 1 }')
      seed=$(get "$s" seed); seeds=$(get "$s" seeds)
      range="$seed"; [[ $seeds == 1 ]] || range="$seed–$((seed + seeds - 1))"
      echo "| $b | $kind | $range | $(num "$mean" 1e-6 '%.3f MPa') | $(pct "$err") | $(num "$(get "$s" peak_stress_min_Pa)" 1e-6 '%.3f')–$(num "$(get "$s" peak_stress_max_Pa)" 1e-6 '%.3f') MPa | $(num "$(get "$s" runtime_s)" 1 '%.1f s') |"
    done
  done
  if [[ $quick == 0 ]]; then
    s="$out/prism_separation/summary.json"
    echo
    echo "Run to separation (100 blocks, seed 1, verbatim): peak $(pct "$(get "$s" peak_error_rel)"), tension dissipated against G_f × crack area $(pct "$(get "$s" fracture_energy_error_rel)"), crack area $(num "$(get "$s" crack_area_over_cross_section)" 1 '%.2f') × section, energy balance $(num "$(get "$s" energy_balance_error_rel)" 1 '%.1e'), $(num "$(get "$s" runtime_s)" 1 '%.1f s')."
  fi
  echo
  s="$out/calibrate/summary.json"
  echo "**Calibration** (\`calibrate\`, $(get "$s" seeds) seed(s) per block count, $(num "$(get "$s" step_displacement_m)" 1e9 '%.0f') nm per step): $(num "$(get "$s" runtime_s)" 1 '%.1f s'); the beam's (\`calibrate --material beam\`, the beam's concrete on a 150 mm square prism with the beam's block size, $(get "$out/calibrate_beam/summary.json" seeds) seed(s)): $(num "$(get "$out/calibrate_beam/summary.json" runtime_s)" 1 '%.1f s')."
  echo
  echo "| material | blocks | prism blocks | strength scale | iterations | fitted mean peak | seed spread | converged |"
  echo "|---|---|---|---|---|---|---|---|"
  cal_row() {  # cal_row MATERIAL SUMMARY BLOCKS
    local pb; pb=$(get "$2" "b${3}_prism_blocks"); [[ $pb == null ]] && pb=$3  # a prism calibration from before the field
    echo "| $1 | $3 | $pb | $(num "$(get "$2" "b${3}_strength_scale")" 1 '%.4f') | $(get "$2" "b${3}_iterations") | $(pct "$(get "$2" "b${3}_peak_error_rel")") | $(num "$(get "$2" "b${3}_peak_spread_rel")" 100 '%.1f %%') | $(get "$2" "b${3}_converged") |"
  }
  for b in "${blocks_list[@]}"; do cal_row prism "$s" "$b"; done
  if [[ $quick == 1 ]]; then beam_cal_blocks=(60); else beam_cal_blocks=(250 500); fi
  for b in "${beam_cal_blocks[@]}"; do cal_row beam "$out/calibrate_beam/summary.json" "$b"; done
  echo
  echo "**RC tie** (100 blocks, seed 1; references: N_cr = f_T (A_c + n A_s), shear-lag K0, f_y A):"
  echo
  echo "| parameters | first cracking | K0 | load drops | crack sites | yield plateau | run time |"
  echo "|---|---|---|---|---|---|---|"
  for kind in verbatim calibrated; do
    s="$out/tie_$kind/summary.json"
    echo "| $kind | $(num "$(get "$s" first_crack_force_N)" 1e-3 '%.2f kN') ($(pct "$(get "$s" first_crack_error_rel)")) | $(num "$(get "$s" initial_stiffness_N_per_m)" 1e-6 '%.1f kN/mm') ($(pct "$(awk -v k="$(get "$s" initial_stiffness_N_per_m)" -v r="$(get "$s" initial_stiffness_shear_lag_N_per_m)" 'BEGIN { print k / r - 1 }')")) | $(get "$s" load_drops) | $(get "$s" crack_sites) | $(num "$(get "$s" yield_force_N)" 1e-3 '%.2f kN') ($(pct "$(get "$s" yield_force_error_rel)")) | $(num "$(get "$s" runtime_s)" 1 '%.1f s') |"
  done
  echo
  echo "**RC beam** (provisional geometry, to 6 mm or --quick; references: first cracking at the flexural strength (MC2010) and at f_T, uncracked K0 with shear, A_s f_y z, the study's 90 mm crack spacing):"
  echo
  echo "| blocks | seed | plates | compression | parameters | first cracking | K0 | yield | peak | flexural cracks | spacing | failure | energy balance | run time |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  for b in "${beam_list[@]}"; do
    s="$out/beam_$b/summary.json"
    params=$(get "$s" parameters | tr -d '"'); [[ $params == null ]] && params=verbatim  # runs from before the field
    [[ $params == calibrated ]] && params="calibrated (× $(num "$(get "$s" strength_scale)" 1 '%.3f'))"
    plates=$(get "$s" plates | tr -d '"'); [[ $plates == null ]] && plates=tied  # runs from before the field
    echo "| $(get "$s" blocks) | $(get "$s" seed) | $plates | $(get "$s" compression | tr -d '"') | $params | $(num "$(get "$s" first_crack_load_N)" 1e-3 '%.2f kN') ($(pct "$(get "$s" first_crack_flexural_error_rel)"); at f_T $(pct "$(get "$s" first_crack_error_rel)")) | $(num "$(get "$s" initial_stiffness_N_per_m)" 1e-6 '%.1f kN/mm') ($(pct "$(get "$s" initial_stiffness_error_rel)")) | $([[ $(get "$s" steel_yielded) == true ]] && echo "$(num "$(get "$s" yield_load_N)" 1e-3 '%.2f kN') ($(pct "$(get "$s" yield_error_rel)"))" || echo "not yielded") | $(num "$(get "$s" peak_load_N)" 1e-3 '%.2f kN')$([[ $(get "$s" failure_reached) == false ]] && echo " (no failure by the stop: the highest load)") | $(get "$s" flexural_cracks) | $(num "$(get "$s" mean_crack_spacing_m)" 1e3 '%.0f mm') | $(get "$s" failure_mode | tr -d '"') (widest crack) | $(num "$(get "$s" energy_balance_error_rel)" 1 '%.1e') | $(num "$(get "$s" runtime_s)" 1 '%.0f s') |"
  done
  if [[ $quick == 0 && $beam_seeds -gt 1 ]]; then
    # The seed band of each block count: min-max of each figure over seeds 1..N.
    band() {  # band BLOCKS KEY SCALE FORMAT
      for ((k = 1; k <= beam_seeds; ++k)); do get "$out/beam_${1}_s$k/summary.json" "$2"; done |
        awk -v s="$3" -v f="$4" '$1 != "null" { v = $1 * s; if (n++ == 0 || v < lo) lo = v; if (n == 1 || v > hi) hi = v }
          END { if (n == 0) print "—"; else printf f "–" f, lo, hi }'
    }
    echo
    echo "Seed band (seeds 1–$beam_seeds, min–max):"
    echo
    echo "| blocks | first cracking | K0 | yield | peak | flexural cracks | spacing | run time |"
    echo "|---|---|---|---|---|---|---|---|"
    for b in 250 500; do
      echo "| $b | $(band $b first_crack_load_N 1e-3 '%.2f') kN | $(band $b initial_stiffness_N_per_m 1e-6 '%.1f') kN/mm | $(band $b yield_load_N 1e-3 '%.2f') kN | $(band $b peak_load_N 1e-3 '%.2f') kN | $(band $b flexural_cracks 1 '%.0f') | $(band $b mean_crack_spacing_m 1e3 '%.0f') mm | $(band $b runtime_s 1 '%.0f') s |"
    done
  fi
  for scene in prism tie; do
    echo
    echo "**Error against run time, $scene** (\`work_precision_figures --scene $scene$([[ $quick == 1 ]] && echo ' --quick')\`; DESIGN.md §7):"
    echo
    cat "$out/work_precision_$scene/table.md"
    echo
    cat "$out/work_precision_$scene/figures.md"
  done
  echo
  s="$out/sensitivity/summary.json"
  echo "**Sensitivity studies** (\`rc_tie_sensitivity$([[ $quick == 1 ]] && echo ' --quick')\`, $(get "$s" runs) runs, $(num "$(get "$s" runtime_s)" 1 '%.0f s')):"
  echo
  echo "| run | first cracking | K0 | load drops | yield plateau | curve difference to the baseline |"
  echo "|---|---|---|---|---|---|"
  awk -F'"' '/_variant":/ { print $2 }' "$s" | while read -r key; do
    p="${key%_variant}"
    echo "| ${p%_*}: $(get "$s" "$key" | tr -d '"') | $(num "$(get "$s" "${p}_first_crack_force_N")" 1e-3 '%.2f kN') | $(num "$(get "$s" "${p}_initial_stiffness_N_per_m")" 1e-6 '%.1f kN/mm') | $(get "$s" "${p}_load_drops") | $(num "$(get "$s" "${p}_yield_force_N")" 1e-3 '%.2f kN') | $(num "$(get "$s" "${p}_curve_error_vs_baseline_rel")" 100 '%.1f %%') |"
  done
} > "$report.tmp"
mv "$report.tmp" "$report"
echo "validate: wrote $report"

if [[ $quick == 0 ]]; then
  doc="$root/docs/studies/validate_run.md"
  begin='<!-- validate.sh: generated tables begin -->'
  end='<!-- validate.sh: generated tables end -->'
  if ! grep -qF "$begin" "$doc" || ! grep -qF "$end" "$doc"; then
    echo "validate: $doc has no generated-section markers" >&2
    exit 1
  fi
  awk -v b="$begin" -v e="$end" -v f="$report" '
    $0 == b { print; while ((getline line < f) > 0) print line; skip = 1; next }
    $0 == e { skip = 0 }
    !skip { print }' "$doc" > "$doc.tmp"
  mv "$doc.tmp" "$doc"
  echo "validate: replaced the generated section of $doc"
  python3 "$root/docs/tables.py" --results "$out" --write
fi
