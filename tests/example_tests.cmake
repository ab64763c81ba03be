# CTest entries that run the example drivers in --quick mode and check their summary.json
# (included from tests/CMakeLists.txt when examples are built). Owners of other examples append
# their entries at the end:
#
#   tessera_add_example_test(<target>
#     [NAME <test name>]            default example_<target>_quick
#     [ARGS <arg>...]               driver arguments; --out is added (build/tests/example_out/<name>)
#     [CHECKS "<key> <OP> <value>"...]  numeric/string checks on summary.json (if() operators)
#     [FILES <file>...]             outputs that must exist besides summary.json
#     [TIMEOUT <s>] [LABELS <label>...])
#
# The test fails if the driver exits non-zero, an output is missing, a key is missing or null
# (but for a check "<key> IS NULL", which asks for null), or a check is false; the driver's stdout is
# shown with --output-on-failure.
function(tessera_add_example_test target)
  cmake_parse_arguments(PARSE_ARGV 1 ex "" "NAME;TIMEOUT" "ARGS;CHECKS;FILES;LABELS")
  # tests/ is configured before examples/, so the driver's target does not exist yet: test its source.
  if(NOT EXISTS ${PROJECT_SOURCE_DIR}/examples/${target}/main.cpp)
    return()
  endif()
  if(NOT ex_NAME)
    set(ex_NAME example_${target}_quick)
  endif()
  if(NOT ex_TIMEOUT)
    set(ex_TIMEOUT 300)
  endif()
  string(REPLACE ";" "|" args "${ex_ARGS}")
  string(REPLACE ";" "|" checks "${ex_CHECKS}")
  string(REPLACE ";" "|" files "${ex_FILES}")
  add_test(NAME ${ex_NAME}
           COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:${target}>
                   -DOUT=${CMAKE_CURRENT_BINARY_DIR}/example_out/${ex_NAME}
                   "-DARGS=${args}" "-DCHECKS=${checks}" "-DFILES=${files}"
                   -P ${CMAKE_CURRENT_LIST_DIR}/check_example.cmake)
  set_tests_properties(${ex_NAME} PROPERTIES TIMEOUT ${ex_TIMEOUT} LABELS "example;${ex_LABELS}")
  # A driver on N threads takes N of ctest's -j slots: two 2-thread drivers side by side on this
  # 2-core machine wait at every step's barrier for a descheduled thread (CI, ctest -j2: the quick
  # beam and reclose overlapping took 293 s and > 300 s; alone, 7.7 s and 4.5 s).
  list(FIND ex_ARGS --threads ti)
  if(ti GREATER -1)
    math(EXPR ti "${ti} + 1")
    list(GET ex_ARGS ${ti} nthreads)
    if(nthreads GREATER 1)
      set_tests_properties(${ex_NAME} PROPERTIES PROCESSORS ${nthreads})
    endif()
  endif()
endfunction()

# ---- tessellate: a conforming tessellation and a valid zoning of the study's prism ----
tessera_add_example_test(tessellate
  ARGS --quick --seed 3
  FILES blocks.vtu zones.vtu
  CHECKS "blocks EQUAL 20"
         "volume_error_rel LESS 1e-12"
         "unmatched_faces EQUAL 0"
         "open_cells EQUAL 0"
         "nonconvex_cells EQUAL 0"
         "regularize_min_edge_rel EQUAL 0"
         "min_zone_volume GREATER 0"
         "zones_per_block_mean GREATER_EQUAL 12")
# The --help text must list the standard options (DESIGN.md §5).
if(EXISTS ${PROJECT_SOURCE_DIR}/examples/tessellate/main.cpp)
  add_test(NAME example_tessellate_help COMMAND $<TARGET_FILE:tessellate> --help)
  set_tests_properties(example_tessellate_help PROPERTIES LABELS example
    PASS_REGULAR_EXPRESSION "--out DIR.*--quick.*--seed N.*--threads N.*--blocks N.*--size LX LY LZ.*--lloyd K.*--help")
  add_test(NAME example_tessellate_bad_flag COMMAND $<TARGET_FILE:tessellate> --blocs 3)
  set_tests_properties(example_tessellate_bad_flag PROPERTIES LABELS example
    PASS_REGULAR_EXPRESSION "tessellate: unknown option '--blocs'")
endif()

# ---- direct_tension: plain-concrete prism, 100 blocks, quasi-static reduced run (5 nm per step,
# half-cosine ramp, stopped at 70 % of the peak on the softening branch) ----
# Measured peak: +10 % over f_T = 2.15 MPa at 2 nm per step and 5 mm/s (+13 % at 5 nm). The excess
# is the shear carried across inclined faces of the tortuous crack (summary peak_shear_part_Pa,
# about 0.8 MPa; docs/architecture.md "Direct tension results"), so the check brackets the model's
# value instead of asserting f_T within 5 %: a change that moves the peak out of [+3 %, +16 %]
# must be explained there.
tessera_add_example_test(direct_tension
  ARGS --quick --seed 1 --threads 1
  FILES curve.csv contacts_peak.vtp contacts_end.vtp zones_peak.vtu zones_end.vtu direct_tension.pvd
  CHECKS "peak_error_rel GREATER 0.03"
         "peak_error_rel LESS 0.16"
         "peak_shear_part_Pa GREATER 2e5"
         "reaction_imbalance_max LESS 0.15"
         "energy_balance_error_rel LESS 0.01"
         "initial_modulus_error_rel LESS 0.05"
         "initial_modulus_error_rel GREATER -0.05"
         "zones GREATER 2000"
         "steps GREATER 10000"
  TIMEOUT 300)

# The same reduced run with the cohesion softening together with the tensile strength
# (--cohesion coupled, docs/model.md "Cohesion and tensile damage"). Measured (quick, seed 1):
# peak +10.1 % (decoupled +13.2 %), shear part over the crack 0.57 MPa (decoupled 0.89 MPa). The
# checks pin the direction of the effect: less shear across the crack and a lower peak.
tessera_add_example_test(direct_tension NAME example_direct_tension_coupled_quick
  ARGS --quick --seed 1 --threads 1 --cohesion coupled
  FILES curve.csv
  CHECKS "peak_error_rel GREATER 0.03"
         "peak_error_rel LESS 0.12"
         "peak_shear_part_Pa LESS 7e5"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)

# The same reduced run by kinetic dynamic relaxation (--scheme relaxation; solver/relaxation.hpp,
# docs/guide.md): increments of 2 um, each relaxed until the largest nodal unbalanced force is
# 1e-3 f_T A. Every sample is a static equilibrium, so the peak is the static one: the implicit
# solve of this tessellation (docs/performance.md, "An implicit quasi-static solve") peaks at
# 2.320 MPa, and the relaxed run must land within [-2.6 %, +1.3 %] of it (measured 2.299 MPa,
# -0.9 %; the explicit run at 2 nm a step peaks at 2.376 MPa, above the band). Measured: 42
# increments, 217 resets, 12 236 steps; E0 +3.0 %.
tessera_add_example_test(direct_tension NAME example_direct_tension_relaxation_quick
  ARGS --quick --seed 1 --threads 1 --scheme relaxation
  FILES curve.csv contacts_peak.vtp
  CHECKS "scheme STREQUAL relaxation"
         "peak_stress_Pa GREATER 2.26e6"
         "peak_stress_Pa LESS 2.35e6"
         "initial_modulus_error_rel LESS 0.05"
         "initial_modulus_error_rel GREATER -0.05"
         "kinetic_to_elastic_at_peak LESS 1e-4"
         "relaxation_unconverged_increments EQUAL 0"
         "relaxation_resets GREATER 0"
         "steps LESS 20000"
  TIMEOUT 300)

# The same reduced run on rounder cells (--lloyd 10: ten Lloyd steps of the tessellation;
# docs/model.md, section 1). This is the issue's acceptance tolerance, peak within 5 % of f_T, which the
# 100-block prism meets on such cells. Measured (quick, seeds 1-3): +1.0, -0.7, -0.3 %, shear part
# over the crack 0.43 MPa for seed 1 (plain Voronoi 0.89); full runs, seeds 1-5: -4.2...+0.8 %.
tessera_add_example_test(direct_tension NAME example_direct_tension_lloyd_quick
  ARGS --quick --seed 1 --threads 1 --lloyd 10
  FILES curve.csv
  CHECKS "peak_error_rel LESS 0.05"
         "peak_error_rel GREATER -0.05"
         "peak_shear_part_Pa LESS 6e5"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
# The same reduced run with the cohesion calibrated to c_0 = 1.2 f_T (--cohesion-ratio 1.2; the
# study and the default: 2): the issue's tolerance, peak within 5 % of f_T, which this cohesion
# meets for 100, 250 and 500 blocks (docs/validation.md "Plain prism": full runs -1.5...+2.2 %). Measured
# (quick, seed 1): -1.3 %, shear part over the crack 0.28 MPa (c_0 = 2 f_T: +13.2 %, 0.89 MPa).
tessera_add_example_test(direct_tension NAME example_direct_tension_calibrated_cohesion_quick
  ARGS --quick --seed 1 --threads 1 --cohesion-ratio 1.2
  FILES curve.csv
  CHECKS "peak_error_rel LESS 0.05"
         "peak_error_rel GREATER -0.05"
         "peak_shear_part_Pa LESS 5e5"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
# The same reduced run on regularised cells (--regularize 0.2: edges shorter than 0.2 x the mean
# cell size collapsed, as Neper does; docs/model.md, section 1). Measured (quick, seed 1): 1526
# sub-contacts and 2010 zones (plain 2079 and 3004), peak +8.1 % (plain +13.2 %), 2.6 s. The checks
# pin that the flag reaches the tessellation and that the peak stays between the two.
tessera_add_example_test(direct_tension NAME example_direct_tension_regularized_quick
  ARGS --quick --seed 1 --threads 1 --regularize 0.2
  FILES curve.csv
  CHECKS "subcontacts LESS 1600"
         "zones LESS 2100"
         "peak_error_rel LESS 0.12"
         "peak_error_rel GREATER 0.04"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)

# ---- rc_tie: the study's RC tie, 100 blocks, reduced run (mass-scaled dt 4e-6 s, 10 mm/s) ----
# Bond stiffness per unit bar length, symmetric pull (the defaults). Measured (quick, seed 1):
# first crack 15.2 kN (hand 10.6 kN, +43 %: the quick run is coarse and the tortuous-crack shear
# excess of the plain prism adds ~10 %), K0 82.1 kN/mm vs the shear-lag value 85.6 (-4 %), 2 load
# drops, 2 fully opened through-cracks (2 crack sites; 4 softened), yield plateau 21.4 kN (f_y A = 20.1 kN,
# +6.5 %; final branch +7.1 %; yield = sustained plastic flow of the bar), energy balance error
# 5.2e-5; the first sub-contact softens at 4.7 kN and at the first crack the concrete carries
# 1.33 f_T with 835 sub-contacts past their peak (docs/validation.md "RC tie"). The
# acceptance tolerances of issue 4 (first cracking within 10 %, yield within 2 %) are NOT met yet
# (docs/validation.md "Known gaps"), so the checks below are the tolerances the model meets today.
tessera_add_example_test(rc_tie
  ARGS --quick --seed 1 --threads 1
  FILES curve.csv bare_bar.csv tie.pvd yield_contacts.vtp yield_bar.vtp yield_zones.vtu
  CHECKS "yield_force_N GREATER 15000"
         "yield_force_error_rel LESS 0.15"
         "initial_stiffness_shear_lag_error_rel LESS 0.15"
         "first_crack_error_rel LESS 0.6"
         "final_force_error_rel LESS 0.1"
         "cracks GREATER 0"
         "crack_sites GREATER 0"
         "crack_site_spacing_m GREATER 0.0302"
         "crack_site_spacing_m LESS 0.0304"
         "bar_crossing_cracks GREATER 0"
         "softened_cracks GREATER 1"
         "energy_balance_error_rel LESS 0.01"
         "subcontacts GREATER 2000"
         "first_softening_force_N LESS 7000"
         "concrete_stress_at_first_crack_over_f_T GREATER 1.0"
         "concrete_stress_at_first_crack_over_f_T LESS 1.5"
  TIMEOUT 300)
# The same reduced tie with one damage for tension and shear (--cohesion coupled and
# --slip-breaks-tension, docs/model.md "Shear failure and tension"). The decoupled law's yield
# plateau sits above f_y A because faces of the yielded crack that slipped keep their tension and
# softening faces keep c_0. Measured (quick, seed 1): final branch +1.65 % (decoupled +7.1 %),
# yield plateau +2.2 % (+6.5 %); full runs, seeds 1-3: final +0.5...+0.6 %. The checks pin it.
tessera_add_example_test(rc_tie NAME example_rc_tie_brittle_quick
  ARGS --quick --seed 1 --threads 1 --no-vtk --cohesion coupled --slip-breaks-tension
  FILES curve.csv
  CHECKS "final_force_error_rel LESS 0.03"
         "final_force_error_rel GREATER -0.02"
         "yield_force_error_rel LESS 0.04"
         "cracks GREATER 0"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
# A block count outside Table 1 (150): the contacts take Table 1's 100-block stiffnesses times
# 1.5^(1/3) (law::scaled_prism_params), k_n = 1.3279e12 Pa/m. Measured (quick, to 0.3 mm, 2 s):
# K0 +8.4 % against the shear-lag value, energy balance 1.0e-4.
tessera_add_example_test(rc_tie NAME example_rc_tie_scaled_blocks_quick
  ARGS --quick --seed 1 --threads 1 --no-vtk --blocks 150 --max-elongation 3e-4
  FILES curve.csv
  CHECKS "contact_stiffness STREQUAL table1_scaled_cbrt"
         "k_n_Pa_per_m GREATER 1.3266e12"
         "k_n_Pa_per_m LESS 1.3292e12"
         "initial_stiffness_shear_lag_error_rel LESS 0.15"
         "initial_stiffness_shear_lag_error_rel GREATER -0.15"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
# The out-of-balance rate control (tessera/solver/balance.hpp): the quick tie with the rate free
# to fall to half and rise to twice --rate. Measured (quick, seed 1, to 0.3 mm, 13 400 steps): at
# this coarse setting the ratio (largest nodal unbalanced force / N_cr) hovers at 0.001-0.003 on
# the elastic branch, so the rate rises (to 1.06x) and falls back; from just before the first
# peak (14.3 kN) it is 0.004-0.03 and the rate stays at half; mean factor 0.579. A fixed rate
# gives a mean factor of 1, a control that never recovered 0.5.
tessera_add_example_test(rc_tie NAME example_rc_tie_rate_control_quick
  ARGS --quick --seed 1 --threads 1 --no-vtk --max-elongation 3e-4 --min-rate-factor 0.5 --max-rate-factor 2
  FILES curve.csv
  CHECKS "mean_rate_factor GREATER 0.55"
         "mean_rate_factor LESS 0.65"
         "max_unbalanced_ratio GREATER 0.01"
         "max_rate_factor GREATER 1.99"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
# The reduced tie by kinetic dynamic relaxation (--scheme relaxation; solver/relaxation.hpp,
# docs/guide.md): 10 um increments of elongation, each relaxed until the largest nodal unbalanced
# force and the largest block resultant are 1e-3 N_cr. Every sample is a static equilibrium, so
# the first crack lands on the converged explicit runs' first drop (five-seed mean 12.46 kN,
# docs/validation.md; measured 12.35 kN), where the quick explicit run overshoots to 15.2 kN, well
# outside the band. Measured (seed 1, to 0.3 mm): K0 -4.2 % of the shear-lag 85.5 kN/mm,
# 30 increments, 292 resets, 59 671 steps, 17 s.
tessera_add_example_test(rc_tie NAME example_rc_tie_relaxation_quick
  ARGS --quick --seed 1 --threads 1 --no-vtk --scheme relaxation --max-elongation 3e-4
  FILES curve.csv
  CHECKS "scheme STREQUAL relaxation"
         "initial_stiffness_shear_lag_error_rel LESS 0.06"
         "first_drop_force_N GREATER 11800"
         "first_drop_force_N LESS 13100"
         "load_drops GREATER 0"
         "relaxation_unconverged_increments EQUAL 0"
         "relaxation_resets GREATER 0"
         "max_unbalanced_ratio LESS 0.003"
         "steps LESS 90000"
  TIMEOUT 300)
# The bare bar by relaxation against its closed form: elastic at E_s A_s / L, then flat at
# f_y A_s. Relaxed to equilibrium the plateau is f_y A_s itself (measured: error 0 to the printed
# digits, K0 +1.5e-4, curve error 9.7e-4 from the 20 um sampling of the kink; 1 820 steps).
tessera_add_example_test(rc_tie NAME example_rc_tie_relaxation_bare_bar
  ARGS --quick --bare --seed 1 --threads 1 --no-vtk --scheme relaxation --relax-increment 2e-5
  FILES curve.csv
  CHECKS "yielded STREQUAL ON"
         "yield_force_error_rel LESS 1e-6"
         "final_force_error_rel LESS 1e-6"
         "initial_stiffness_error_rel LESS 1e-3"
         "bare_bar_curve_error_rel LESS 0.003"
  TIMEOUT 300)
# The reduced tie with the beam's mixed-mode set (--law mixed_mode --g-ii 70, rc_tie/concrete.hpp):
# one damage for tension and shear, linear softening, on the same Table 1 contacts (f_T 2.15 MPa,
# G_f 60 J/m^2), so the hand checks are the study law's. Measured (quick, seed 1): first crack
# 13.97 kN, +32.1 % of f_T (A_c + n A_s) = 10.58 kN (the study's law: 15.18 kN, +43.5 %); 6 load
# drops, 5 fully opened through-cracks at 4 sites (study: 2); yield plateau 20.56 kN, +2.25 % of
# f_y A (study +6.52 %), final branch +2.27 %; energy balance 1.9e-5. The bands: first crack +23 ...
# +40 % (13.0-14.8 kN, the study's quick run is outside), yield and final branch within 4 %.
tessera_add_example_test(rc_tie NAME example_rc_tie_mixed_quick
  ARGS --quick --seed 1 --threads 1 --no-vtk --law mixed_mode --g-ii 70
  FILES curve.csv
  CHECKS "law STREQUAL mixed_mode"
         "g_ii_J_per_m2 EQUAL 70"
         "phi_res_deg EQUAL 30"
         "softening STREQUAL linear"
         "first_crack_force_N GREATER 13000"
         "first_crack_force_N LESS 14800"
         "yield_force_error_rel LESS 0.04"
         "final_force_error_rel LESS 0.04"
         "cracks GREATER 2"
         "bar_crossing_cracks GREATER 2"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
# ---- rc_tie_sensitivity: the Sec. 3.2 studies, reduced set (xi 2 and 4; c_bond 1e9 and 1e4 N/m;
# 100 blocks, dt 4e-6 s, 5 mm/s; 4 runs, about 45 s on one thread) ----
# The study's trends with numbers. Measured (quick, seed 1): K0 66.5 kN/mm for xi = 2 and 82.4 for
# xi = 4; at c_bond = 1e4 N/m the bar slides out of the concrete: K0 16.2 kN/mm (bare bar E_s A_s / L
# = 16.1), no load drop, curve 6.7 % of f_y A from the bare bar's (34.2 % for the perfect bond); yield
# plateau of the baseline 20.63 kN (f_y A = 20.11 kN).
tessera_add_example_test(rc_tie_sensitivity NAME example_rc_tie_sensitivity_quick
  ARGS --quick --seed 1 --threads 1
  FILES xi.csv xi.png xi_table.csv cbond.csv cbond_table.csv runtime_table.csv trends.md
  CHECKS "runs EQUAL 4"
         "xi_initial_stiffness_sorted STREQUAL ON"
         "xi_0_initial_stiffness_N_per_m LESS 7.5e7"
         "xi_1_initial_stiffness_N_per_m GREATER 7.5e7"
         "xi_1_yield_force_N GREATER 19900"
         "xi_1_yield_force_N LESS 21500"
         "cbond_0_curve_error_vs_bare_bar_rel GREATER 0.25"
         "cbond_1_curve_error_vs_bare_bar_rel LESS 0.1"
         "cbond_1_initial_stiffness_N_per_m GREATER 1.5e7"
         "cbond_1_initial_stiffness_N_per_m LESS 1.75e7"
         "cbond_1_load_drops EQUAL 0"
  TIMEOUT 600)

# ---- bad input, tried as a hostile user would (issue: every flag checked before anything is
# written): a non-zero exit, a message naming the flag and the value, no output directory ----
function(tessera_add_refusal_test name target expect)
  if(NOT EXISTS ${PROJECT_SOURCE_DIR}/examples/${target}/main.cpp)
    return()
  endif()
  string(REPLACE ";" "|" args "${ARGN}")
  add_test(NAME ${name}
           COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:${target}> -DOUT=${CMAKE_CURRENT_BINARY_DIR}/example_out/${name}
                   "-DARGS=${args}" "-DEXPECT=${expect}" -P ${CMAKE_CURRENT_LIST_DIR}/check_refused.cmake)
  set_tests_properties(${name} PROPERTIES LABELS example TIMEOUT 120)
endfunction()
tessera_add_refusal_test(refuse_direct_tension_cohesion_ratio direct_tension
  "^direct_tension: --cohesion-ratio: value '-1' must be > 0\n$" --threads 1 --cohesion-ratio -1)
tessera_add_refusal_test(refuse_direct_tension_regularize direct_tension
  "^direct_tension: --regularize: value '0.7' must be <= 0.5\n$" --threads 1 --regularize 0.7)
tessera_add_refusal_test(refuse_direct_tension_dt_nan direct_tension "--dt: invalid value 'nan'" --quick --dt nan)
tessera_add_refusal_test(refuse_direct_tension_dt_negative direct_tension "--dt: value '-1' must be >= 0" --quick --dt -1)
tessera_add_refusal_test(refuse_direct_tension_step_zero direct_tension "--step-displacement: value '0' must be > 0"
  --quick --step-displacement 0)
tessera_add_refusal_test(refuse_direct_tension_max_displacement direct_tension "--max-displacement: value '-1' must be > 0"
  --quick --max-displacement -1)
tessera_add_refusal_test(refuse_direct_tension_seeds direct_tension "--seeds: value '1000000' must be <= 1000"
  --seeds 1000000)
tessera_add_refusal_test(refuse_direct_tension_dt_not_quasi_static direct_tension
  "loading rate 0.005 m/s with added mass .* is not quasi-static.*use a rate <=" --quick --threads 1 --dt 1)
tessera_add_refusal_test(refuse_direct_tension_relaxation_rigid direct_tension
  "--scheme relaxation relaxes deformable blocks; --rigid is not relaxed" --quick --scheme relaxation --rigid)
tessera_add_refusal_test(refuse_direct_tension_relaxation_rate direct_tension
  "--rate sets the explicit ramp; with --scheme relaxation" --quick --scheme relaxation --rate 0.01)
tessera_add_refusal_test(refuse_direct_tension_relax_flag_explicit direct_tension
  "--relax-increment applies to --scheme relaxation, and this run is --scheme explicit" --quick --relax-increment 1e-6)
tessera_add_refusal_test(refuse_direct_tension_relax_tolerance direct_tension
  "--relax-tolerance: value '2' must be <= 1" --quick --scheme relaxation --relax-tolerance 2)
tessera_add_refusal_test(refuse_direct_tension_relax_increment direct_tension
  "--relax-increment 0.001 m exceeds --max-displacement 0.0002 m" --quick --scheme relaxation --relax-increment 1e-3)
tessera_add_refusal_test(refuse_rc_tie_relaxation_rigid rc_tie
  "--scheme relaxation relaxes deformable blocks; --rigid is not relaxed" --quick --scheme relaxation --rigid)
tessera_add_refusal_test(refuse_rc_tie_relaxation_rate rc_tie
  "--rate sets the explicit pull; with --scheme relaxation" --quick --scheme relaxation --rate 0.01)
tessera_add_refusal_test(refuse_rc_tie_relaxation_dt rc_tie
  "--dt sets the explicit pull; with --scheme relaxation" --quick --scheme relaxation --dt 1e-6)
tessera_add_refusal_test(refuse_rc_tie_relax_flag_explicit rc_tie
  "--relax-increment applies to --scheme relaxation, and this run is --scheme explicit" --quick --relax-increment 1e-6)
tessera_add_refusal_test(refuse_rc_tie_relax_tolerance rc_tie
  "--relax-tolerance: value '2' must be <= 1" --quick --scheme relaxation --relax-tolerance 2)
tessera_add_refusal_test(refuse_rc_tie_relax_increment rc_tie
  "--relax-increment 0.01 m exceeds --max-elongation 0.002 m" --quick --scheme relaxation --relax-increment 1e-2)
tessera_add_refusal_test(refuse_rc_tie_scheme rc_tie
  "--scheme: invalid value 'implicit' \\(expected explicit or relaxation\\)" --quick --scheme implicit)
tessera_add_refusal_test(refuse_rc_tie_lloyd rc_tie "^rc_tie: --lloyd: value '-1' must be >= 0\n$" --threads 1 --lloyd -1)
tessera_add_refusal_test(refuse_rc_tie_cohesion_ratio rc_tie "^rc_tie: --cohesion-ratio: value '-1' must be > 0\n$"
  --threads 1 --cohesion-ratio -1)
tessera_add_refusal_test(refuse_rc_tie_dt_not_quasi_static rc_tie "loading rate 0.01 m/s .* is not quasi-static"
  --quick --threads 1 --no-vtk --dt 1)
tessera_add_refusal_test(refuse_rc_tie_rate rc_tie "loading rate 1000000 m/s .* is not quasi-static.*use a rate <="
  --quick --threads 1 --no-vtk --rate 1e6)
tessera_add_refusal_test(refuse_rc_tie_rate_control_fast rc_tie
  "fastest rate of the out-of-balance control.*loading rate 1 m/s .* is not quasi-static"
  --quick --threads 1 --no-vtk --max-rate-factor 100)
tessera_add_refusal_test(refuse_rc_tie_rate_control_bands rc_tie
  "adaptive rate: ratios low 0.01 and high 0.005 must satisfy 0 < low < high"
  --quick --threads 1 --no-vtk --balance-low 0.01 --balance-high 0.005)
tessera_add_refusal_test(refuse_rc_tie_min_rate_factor rc_tie "--min-rate-factor: value '0' must be > 0"
  --min-rate-factor 0)
tessera_add_refusal_test(refuse_rc_tie_elements rc_tie "--elements: value '1000000000' must be <= 100000"
  --elements 1000000000)
tessera_add_refusal_test(refuse_rc_tie_threads rc_tie "--threads: value '1000' must be <= 256" --threads 1000)
tessera_add_refusal_test(refuse_rc_tie_threads_negative rc_tie "--threads: value '-1' must be >= 0" --threads -1)
tessera_add_refusal_test(refuse_rc_tie_hex rc_tie "--seed: invalid value '0x10'" --seed 0x10)
tessera_add_refusal_test(refuse_rc_tie_blocks rc_tie "--blocks: value '1000000' must be <= 200000"
  --blocks 1000000)
tessera_add_refusal_test(refuse_rc_tie_blocks_few rc_tie "--blocks: value '10' must be >= 20" --blocks 10)
tessera_add_refusal_test(refuse_rc_tie_softening rc_tie "--softening: invalid value 'foo' \\(expected power or linear\\)"
  --softening foo)
# --law (rc_tie/concrete.hpp): a law not in the list, --g-ii with the study's law or below the mixed
# law's bound c_0^2 / (2 k_s) = 19.2 J/m^2 (refused before anything is written), and the study law's
# flags that the mixed-mode tie does not take, each named with its value.
tessera_add_refusal_test(refuse_rc_tie_law rc_tie "--law: invalid value 'crushing' \\(expected study or mixed_mode\\)"
  --law crushing)
tessera_add_refusal_test(refuse_rc_tie_g_ii_study rc_tie
  "^rc_tie: --g-ii 70 J/m.2 applies to --law mixed_mode only \\(--law study has no G_II\\)" --threads 1 --g-ii 70)
# --phi-res-deg (the spent contact's friction) likewise: the mixed-mode law's only, at most phi_0 = 35.
tessera_add_refusal_test(refuse_rc_tie_phi_res_study rc_tie
  "^rc_tie: --phi-res-deg 15 applies to --law mixed_mode only \\(--law study keeps the study's 30 deg\\)" --threads 1
  --phi-res-deg 15)
tessera_add_refusal_test(refuse_rc_tie_phi_res_range rc_tie "--phi-res-deg: value '40' must be <= 35"
  --threads 1 --law mixed_mode --phi-res-deg 40)
tessera_add_refusal_test(refuse_rc_tie_mixed_g_ii_small rc_tie "G_II = 10 J/m.2 gives s_u .* G_II must exceed"
  --quick --threads 1 --law mixed_mode --g-ii 10)
tessera_add_refusal_test(refuse_rc_tie_mixed_softening rc_tie
  "^rc_tie: --softening power applies to --law study only \\(--law mixed_mode softens linearly over G_f\\)"
  --threads 1 --law mixed_mode --softening power)
tessera_add_refusal_test(refuse_rc_tie_mixed_cohesion rc_tie
  "^rc_tie: --cohesion coupled applies to --law study only" --threads 1 --law mixed_mode --cohesion coupled)
tessera_add_refusal_test(refuse_rc_tie_mixed_slip_breaks rc_tie
  "^rc_tie: --slip-breaks-tension applies to --law study only" --threads 1 --law mixed_mode --slip-breaks-tension)
tessera_add_refusal_test(refuse_rc_tie_mixed_params rc_tie
  "^rc_tie: --params .*calibrated_quick.json applies to --law study only" --threads 1 --law mixed_mode
  --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_quick.json)
tessera_add_refusal_test(refuse_rc_tie_mixed_rigid rc_tie
  "^rc_tie: --rigid applies to --law study only \\(--law mixed_mode is built on deformable blocks\\)"
  --threads 1 --law mixed_mode --rigid)
tessera_add_refusal_test(refuse_rc_tie_mixed_relaxation rc_tie
  "^rc_tie: --scheme relaxation applies to --law study only" --threads 1 --law mixed_mode --scheme relaxation)
tessera_add_refusal_test(refuse_tessellate_edge tessellate "--edge 1e-05 m .* zones, an estimated .* GiB \\(limit 8 GiB\\)"
  --edge 1e-5)
tessera_add_refusal_test(refuse_rc_tie_sensitivity_studies rc_tie_sensitivity "unknown study 'foo'" --studies foo)
# Lists (cli::split_list, shared by calibrate --blocks, rc_tie_sensitivity --studies and
# work_precision_figures --settings): an empty item or a repeat is refused, not skipped or run twice.
tessera_add_refusal_test(refuse_rc_tie_sensitivity_studies_empty rc_tie_sensitivity
  "--studies 'xi,' must be a comma-separated list without empty items" --studies xi,)
tessera_add_refusal_test(refuse_calibrate_blocks_repeat calibrate "--blocks '100,100' lists '100' twice" --threads 1 --blocks 100,100)
if(EXISTS ${PROJECT_SOURCE_DIR}/examples/rc_tie/main.cpp)
  # An empty --out is refused by the parser (no --out is appended here: the empty one is the input).
  add_test(NAME refuse_rc_tie_empty_out COMMAND $<TARGET_FILE:rc_tie> --quick --out "")
  set_tests_properties(refuse_rc_tie_empty_out PROPERTIES LABELS example WILL_FAIL TRUE)
  add_test(NAME example_rc_tie_help COMMAND $<TARGET_FILE:rc_tie> --help)
  set_tests_properties(example_rc_tie_help PROPERTIES LABELS example
    PASS_REGULAR_EXPRESSION "--out DIR.*--quick.*--seed N.*--threads N.*--blocks N.*--elements N.*--xi XI.*--cbond C.*--softening.*--rate V.*--rigid.*--bare")
endif()

# A killed run: run.json says "interrupted", no summary.json, no temporary file; a rerun removes the
# files the killed run listed and nothing else (tests/check_interrupt.sh).
if(EXISTS ${PROJECT_SOURCE_DIR}/examples/rc_tie/main.cpp)
  add_test(NAME example_rc_tie_interrupted
           COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/check_interrupt.sh $<TARGET_FILE:rc_tie>
                   ${CMAKE_CURRENT_BINARY_DIR}/example_out/rc_tie_interrupted --threads 1)
  set_tests_properties(example_rc_tie_interrupted PROPERTIES LABELS example TIMEOUT 300)
endif()

# A long run is visibly alive from its first minute (tests/check_alive.sh): a 60-block beam to its
# default deflection (tens of minutes) with stderr to a file shows run.json "running" and a
# progress line, then is interrupted.
if(EXISTS ${PROJECT_SOURCE_DIR}/examples/rc_beam/main.cpp)
  add_test(NAME example_rc_beam_alive
           COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/check_alive.sh $<TARGET_FILE:rc_beam>
                   ${CMAKE_CURRENT_BINARY_DIR}/example_out/rc_beam_alive --blocks 60 --no-vtk --threads 1)
  set_tests_properties(example_rc_beam_alive PROPERTIES LABELS example TIMEOUT 900)
endif()

# ParaView-ready outputs: every VTK file of a quick tie read back with VTK's own XML readers
# (python3-vtk9, installed by cmake/install-deps.sh): counts, no NaN, one name per quantity,
# reference configuration + displacement (tests/check_vtk_files.py). Debian's own python3, where
# python3-vtk9 installs (a python3 first on PATH, e.g. pyenv's, does not see it).
find_program(TESSERA_SYSTEM_PYTHON NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT TESSERA_SYSTEM_PYTHON)
  set(TESSERA_SYSTEM_PYTHON python3)
endif()
foreach(driver rc_tie direct_tension)
  if(EXISTS ${PROJECT_SOURCE_DIR}/examples/${driver}/main.cpp)
    add_test(NAME example_${driver}_vtk_files
             COMMAND ${TESSERA_SYSTEM_PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_vtk_files.py $<TARGET_FILE:${driver}>
                     ${CMAKE_CURRENT_BINARY_DIR}/example_out/${driver}_vtk_files --quick --threads 1)
    set_tests_properties(example_${driver}_vtk_files PROPERTIES LABELS example TIMEOUT 300)
  endif()
endforeach()

# ---- calibrate: the strength fit on the quick prism (100 blocks, seed 1, 5 nm per step) ----
# The secant on the mean peak converges in 4 iterations to s = 0.830 (peak +0.19 % of f_T;
# the study verbatim, s = 1, gives +13.2 %); about 10 s. The scale's band pins the physics: the
# 100-block prism needs its contacts about 17 % weaker than f_T to peak at f_T.
tessera_add_example_test(calibrate
  ARGS --quick --seed 1 --threads 1
  FILES calibrated.json calibration.csv
  CHECKS "converged_count EQUAL 1"
         "peak_error_rel_max_abs LESS 0.01"
         "b100_strength_scale GREATER 0.78"
         "b100_strength_scale LESS 0.88"
  TIMEOUT 300)
# The parameters calibrate --quick wrote (tests/data/calibrated_quick.json, the same recipe) loaded
# by direct_tension --params reproduce the calibrated peak within 1 % of f_T. If the physics
# changes, this fails until the file is regenerated:
#   calibrate --quick --seed 1 --out DIR && cp DIR/calibrated.json tests/data/calibrated_quick.json
tessera_add_example_test(direct_tension NAME example_direct_tension_params_quick
  ARGS --quick --seed 1 --threads 1 --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_quick.json
  FILES curve.csv
  CHECKS "peak_error_rel LESS 0.01"
         "peak_error_rel GREATER -0.01"
         "strength_scale LESS 0.88"
  TIMEOUT 300)
tessera_add_refusal_test(refuse_calibrate_blocks calibrate
  "^calibrate: --blocks '100,120': '120' is not one of 100, 250, 500, 750 \\(Table 1\\)\n$" --threads 1 --blocks 100,120)
tessera_add_refusal_test(refuse_direct_tension_params_blocks direct_tension
  "has no entry for 250 blocks \\(it has 100\\)"
  --threads 1 --quick --blocks 250 --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_quick.json)
tessera_add_refusal_test(refuse_direct_tension_params_law direct_tension
  "was fitted with power softening, this run uses linear"
  --threads 1 --quick --softening linear --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_quick.json)

# Contact detection with rigid blocks (examples/verification, quick durations, each under a second):
# the four closed-form problems on both sides of their boundaries. Measured errors are in
# docs/validation.md "Contact detection".
tessera_add_example_test(verification NAME example_verification_incline_stick_quick
  ARGS --quick --threads 1 --case incline --angle-deg 20 --friction-deg 30
  FILES curve.csv blocks_final.vtu
  CHECKS "pass STREQUAL ON" "measured LESS 1e-6" "subcontacts EQUAL 4")
tessera_add_example_test(verification NAME example_verification_incline_slide_quick
  ARGS --quick --threads 1 --case incline --angle-deg 40 --friction-deg 30
  CHECKS "pass STREQUAL ON" "error_rel LESS 1e-3" "error_rel GREATER -1e-3" "energy_error_rel LESS 1e-3")
tessera_add_example_test(verification NAME example_verification_topple_stable_quick
  ARGS --quick --threads 1 --case topple --aspect 0.5 --friction-deg 40 --angle-deg 25
  CHECKS "pass STREQUAL ON" "mode STREQUAL stable")
tessera_add_example_test(verification NAME example_verification_topple_quick
  ARGS --quick --threads 1 --case topple --aspect 0.5 --friction-deg 40 --angle-deg 28.5
  CHECKS "pass STREQUAL ON" "mode STREQUAL topple")
tessera_add_example_test(verification NAME example_verification_stack_quick
  ARGS --quick --threads 1 --case stack --blocks 5
  CHECKS "pass STREQUAL ON" "error_rel LESS 1e-6" "error_rel GREATER -1e-6" "drift_m LESS 1e-9")
tessera_add_example_test(verification NAME example_verification_drop_quick
  ARGS --quick --threads 1 --case drop
  CHECKS "pass STREQUAL ON" "error_rel LESS 0.01" "error_rel GREATER -0.01")
# reclose (quick: the push begins at 60 % of the peak on the softening branch; about 7 s): the
# closed crack's compressive stiffness against the intact one, measured +0.14 %.
tessera_add_example_test(verification NAME example_verification_reclose_quick
  ARGS --quick --threads 2 --case reclose
  FILES curve.csv
  CHECKS "pass STREQUAL ON" "error_rel LESS 0.02" "error_rel GREATER -0.02" "energy_error_rel LESS 1e-3"
  TIMEOUT 300)
# bond: a bonded cube fails in shear and slides on its broken face (the hand-over of a bonded face
# to detected contacts with its residual state); failure force and acceleration within 1 %.
tessera_add_example_test(verification NAME example_verification_bond_quick
  ARGS --quick --threads 1 --case bond --angle-deg 40 --friction-deg 30
  FILES curve.csv blocks_final.vtu
  CHECKS "pass STREQUAL ON" "error_rel LESS 0.01" "error_rel GREATER -0.01" "acceleration_error LESS 0.01"
         "acceleration_error GREATER -0.01" "bonded_at_start EQUAL 4" "kept_last_rebuild EQUAL 4")
# The same problems with deformable blocks (--deformable: elastic zones, detected contacts at the
# surface gridpoints; docs/model.md "Deformable blocks"): the slide and the drop, under a second each.
tessera_add_example_test(verification NAME example_verification_deformable_slide_quick
  ARGS --quick --threads 2 --case incline --angle-deg 40 --friction-deg 30 --deformable --duration 0.25
  FILES curve.csv blocks_final.vtu
  CHECKS "pass STREQUAL ON" "error_rel LESS 0.01" "error_rel GREATER -0.01" "block_model STREQUAL deformable"
         "subcontacts EQUAL 5")
tessera_add_example_test(verification NAME example_verification_deformable_drop_quick
  ARGS --quick --threads 1 --case drop --deformable
  CHECKS "pass STREQUAL ON" "error_rel LESS 0.01" "error_rel GREATER -0.01" "energy_error_rel LESS 1e-6")
tessera_add_refusal_test(refuse_verification_deformable_bond verification
  "--deformable applies to incline, topple, stack and drop, not to bond" --threads 1 --case bond --angle-deg 40 --deformable)
tessera_add_refusal_test(refuse_verification_zone_edge verification
  "--zone-edge = 0.001 m must lie in" --threads 1 --case drop --deformable --zone-edge 0.001)
tessera_add_refusal_test(refuse_verification_case verification
  "--case: invalid value 'slide'" --threads 1 --case slide)
tessera_add_refusal_test(refuse_verification_cohesion verification
  "--cohesion" --threads 1 --case bond --cohesion -5)
tessera_add_refusal_test(refuse_verification_bond_tilt verification
  "never breaks the bond" --threads 1 --case bond --angle-deg 10)
tessera_add_refusal_test(refuse_verification_angle verification
  "--angle-deg" --threads 1 --case incline --angle-deg 95)
# The rubble scene, 100 blocks for 0.1 s: the cube lands on the floor (its top comes down), contacts
# form between blocks that started apart, the energy balance closes with the rebuild exchange booked.
tessera_add_example_test(rubble
  ARGS --quick --threads 1
  FILES curve.csv rubble.pvd blocks_0000.vtu
  CHECKS "blocks EQUAL 100"
         "subcontacts GREATER 1500"
         "rebuilds GREATER 5"
         "top_z_end_m LESS 0.96"
         "energy_error_rel LESS 0.005"
         "mean_subcontacts GREATER 1000"
         "ns_per_subcontact_step GREATER 0"
         "ns_per_subcontact_step_without_rebuilds GREATER 0")
tessera_add_refusal_test(refuse_rubble_gap rubble "--gap: value '0.5' must be <= 0.2" --threads 1 --gap 0.5)
# ---- rc_beam: the study's RC beam in four-point bending (issue #18), quick: 60 blocks with 50 mm
# face zoning to a little past first cracking (13 s on 2 threads). Checks: a vertical (flexural)
# crack first, inside the constant-moment zone; first cracking against the hand value at the
# flexural tensile strength (fib MC2010; the f_T-based M_cr is 1.5x lower,
# examples/rc_beam/beam.hpp); the energy balance, which with steel plates of their own
# (--plates contact, the default) includes their contact forces' work. The plates: 52 and 61
# sub-contacts, the loading plate's far edge lifted off (60 of 61 in contact) and both plates
# turned by the beam (-1.1 and -0.65 mrad), measured. First cracking 14.11 kN (-14.3 %) with
# plates of their own, 15.11 kN (-8.2 %) with the tied gridpoints (--plates tied, the study's
# driven nodes), whose quick beam is also 10 % stiffer (70.6 against 64.1 kN/mm). ----
tessera_add_example_test(rc_beam
  ARGS --quick --threads 2
  FILES curve.csv cracks.csv hand.csv
  CHECKS "provisional_geometry STREQUAL ON"
         "plates STREQUAL contact"
         "support_plate_subcontacts GREATER 20"
         "loading_plate_subcontacts GREATER 20"
         "loading_plate_in_contact_at_end GREATER 20"
         "loading_plate_rotation_rad LESS 0"
         "first_crack_in_moment_zone STREQUAL ON"
         "vertical_cracks_first STREQUAL ON"
         "first_crack_angle_deg LESS 35"
         "first_crack_flexural_error_rel LESS 0.25"
         "first_crack_flexural_error_rel GREATER -0.25"
         "energy_balance_error_rel LESS 1e-3"
         "span STREQUAL half"
         "elastic_check_load_N GREATER 8.07e3"
         "elastic_check_load_N LESS 8.16e3"
  TIMEOUT 600)
tessera_add_example_test(rc_beam NAME example_rc_beam_tied_quick
  ARGS --quick --threads 2 --no-vtk --plates tied
  FILES curve.csv
  CHECKS "plates STREQUAL tied"
         "vertical_cracks_first STREQUAL ON"
         "first_crack_flexural_error_rel LESS 0.25"
         "first_crack_flexural_error_rel GREATER -0.25"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
# The quick beam by kinetic dynamic relaxation (--scheme relaxation; solver/relaxation.hpp,
# docs/guide.md): the loading plate moved down 10 um an increment, each relaxed until the largest
# nodal unbalanced force and block resultant are 1e-3 of the hand P_cr; the steel plates have no
# inertia in it (platen_motion::quasi_static), without which the resets came every three steps
# and one increment took over 26 000 steps. Every sample is static, so the first crack is read on
# the load itself, not on a smoothed load that lags it: measured 14.78 kN, where the explicit
# runs' load at the same deflection is 14.73 (5 mm/s) and 14.80 kN (2.5 mm/s), and their smoothed
# first crack 14.11 and 14.14 kN; elastic check 8 139 N (explicit 8 115 and 8 137 N); 40
# increments, 276 resets, 14 868 steps.
tessera_add_example_test(rc_beam NAME example_rc_beam_relaxation_quick
  ARGS --quick --threads 1 --no-vtk --scheme relaxation
  FILES curve.csv
  CHECKS "scheme STREQUAL relaxation"
         "vertical_cracks_first STREQUAL ON"
         "first_crack_in_moment_zone STREQUAL ON"
         "first_crack_load_N GREATER 14400"
         "first_crack_load_N LESS 15200"
         "elastic_check_load_N GREATER 8.10e3"
         "elastic_check_load_N LESS 8.18e3"
         "loading_plate_rotation_rad LESS 0"
         "relaxation_unconverged_increments EQUAL 0"
         "relaxation_resets GREATER 0"
         "steps LESS 30000"
  TIMEOUT 300)
tessera_add_refusal_test(refuse_rc_beam_relaxation_rate rc_beam
  "--rate sets the explicit loading; with --scheme relaxation the loading plate moves" --quick --scheme relaxation --rate 0.01)
tessera_add_refusal_test(refuse_rc_beam_relax_increment_explicit rc_beam
  "--relax-increment applies to --scheme relaxation, and this run is --scheme explicit" --quick --relax-increment 1e-5)
tessera_add_refusal_test(refuse_rc_beam_relax_increment rc_beam
  "--relax-increment 0.01 m exceeds --max-deflection 0.002 m" --quick --scheme relaxation --relax-increment 1e-2)
tessera_add_refusal_test(refuse_rc_beam_relaxation_law rc_beam
  "--scheme relaxation is built for the study's law" --quick --scheme relaxation --compression elastic)
tessera_add_refusal_test(refuse_rc_beam_relaxation_checkpoint rc_beam
  "--scheme relaxation keeps no checkpoint" --quick --scheme relaxation --checkpoint x.ckpt)
tessera_add_refusal_test(refuse_rc_beam_plates rc_beam "--plates: invalid value 'glued'" --threads 1 --plates glued)
tessera_add_refusal_test(refuse_rc_beam_plate_thickness rc_beam "--plate-thickness: value '0' must be > 0"
  --threads 1 --plate-thickness 0)
tessera_add_refusal_test(refuse_rc_beam_blocks rc_beam "--blocks: value '600' must be" --threads 1 --blocks 600)
tessera_add_refusal_test(refuse_rc_beam_rate rc_beam "is not quasi-static" --threads 1 --quick --rate 1)
tessera_add_refusal_test(refuse_rc_beam_zone_edge rc_beam "would need about" --threads 1 --zone-edge 1e-4)
tessera_add_refusal_test(refuse_rc_beam_depth rc_beam "effective depth d = 0.2 m must be below h" --threads 1 --depth 0.2)
# Checkpoints: the quick beam (its steel plates' contact states and motion, the samples, events
# and opening history) stopped at 0.3 mm, past its first developed crack at 0.22 mm, with a
# checkpoint and resumed on 2 threads gives the run made in one go to the bit (its 0.45 mm end);
# a resume with another seed is refused.
if(EXISTS ${PROJECT_SOURCE_DIR}/examples/rc_beam/main.cpp)
  add_test(NAME example_rc_beam_resume_quick
           COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:rc_beam> -DOUT=${CMAKE_CURRENT_BINARY_DIR}/example_out/rc_beam_resume
                   "-DARGS=--quick|--no-vtk" "-DFIRST=--threads|1|--max-deflection|3e-4"
                   "-DRESUME=--threads|2" "-DSAME=curve.csv|cracks.csv" "-DOTHER=--seed|7"
                   -P ${CMAKE_CURRENT_LIST_DIR}/check_resumed_run.cmake)
  set_tests_properties(example_rc_beam_resume_quick PROPERTIES LABELS example TIMEOUT 900 PROCESSORS 2)
endif()
tessera_add_refusal_test(refuse_rc_beam_checkpoint_every rc_beam "--checkpoint-every 60 s sets how often --checkpoint saves"
  --threads 1 --checkpoint-every 60)
tessera_add_refusal_test(refuse_rc_beam_checkpoint_every_negative rc_beam "--checkpoint-every: value '-1' must be >= 0"
  --threads 1 --checkpoint x.ckpt --checkpoint-every -1)
tessera_add_refusal_test(refuse_rc_beam_resume_missing rc_beam "cannot open checkpoint 'no/such.ckpt'"
  --threads 1 --resume no/such.ckpt)
# The beam's calibration (calibrate --material beam): the quick recipe (60 beam blocks, 50 mm face
# zoning, as rc_beam --quick) fits on a 37-block 150 x 150 x 600 mm prism of the beam's concrete,
# which peaks +3.5 % above f_T = 2.5 MPa with the study's contacts; the secant converges in 3
# iterations to s = 0.942 (about 5 s). rc_beam --quick then loads the scale it wrote
# (tests/data/calibrated_beam_quick.json; regenerate with
#   calibrate --quick --material beam --seed 1 --out DIR && cp DIR/calibrated.json tests/data/calibrated_beam_quick.json)
# and it cracks at lower loads than with the study's contacts: first cracking (the soffit's mean
# stress at the contacts' strength) 14.09 kN against 15.11 kN, the first crack h/4 deep 14.41 kN
# against 15.46 kN (measured). The fit also records the prism's initial modulus, 31.25 GPa (the
# contacts' k_n on these coarse blocks; the concrete's E is 25 GPa), and rc_beam scales the hand
# stiffness to it: 44.89 x 31.25 / 25 = 56.11 kN/mm.
tessera_add_example_test(calibrate NAME example_calibrate_beam_quick
  ARGS --quick --material beam --seed 1 --threads 1
  FILES calibrated.json calibration.csv
  CHECKS "converged_count EQUAL 1"
         "peak_error_rel_max_abs LESS 0.01"
         "b60_prism_blocks EQUAL 37"
         "b60_strength_scale GREATER 0.9"
         "b60_strength_scale LESS 0.98"
         "b60_initial_modulus_Pa GREATER 2.9e10"
         "b60_initial_modulus_Pa LESS 3.4e10"
  TIMEOUT 300)
tessera_add_example_test(rc_beam NAME example_rc_beam_params_quick
  ARGS --quick --threads 2 --no-vtk --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_beam_quick.json
  FILES curve.csv
  CHECKS "parameters STREQUAL calibrated"
         "strength_scale GREATER 0.9"
         "strength_scale LESS 0.98"
         "model_young_Pa GREATER 3.12e10"
         "model_young_Pa LESS 3.13e10"
         "hand_initial_stiffness_model_modulus_N_per_m GREATER 5.60e7"
         "hand_initial_stiffness_model_modulus_N_per_m LESS 5.62e7"
         "first_crack_load_N LESS 15.0e3"
         "developed_crack_load_N LESS 15.0e3"
         "vertical_cracks_first STREQUAL ON"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
tessera_add_refusal_test(refuse_rc_beam_params_prism rc_beam
  "was fitted on the prism recipe, this run needs the beam recipe"
  --threads 1 --quick --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_quick.json)
tessera_add_refusal_test(refuse_rc_beam_params_modulus rc_beam
  "entries\\[0\\].initial_modulus_mean_Pa = -1 must lie in \\[1e6, 1e13\\] Pa"
  --threads 1 --quick --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_bad_modulus.json)
tessera_add_refusal_test(refuse_rc_beam_params_zoning rc_beam
  "was fitted with a face zoning edge of 0.05 m, this run uses 0.03 m"
  --threads 1 --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_beam_quick.json)
tessera_add_refusal_test(refuse_rc_beam_params_geometry rc_beam
  "was fitted with the blocks of a half beam of 0.02175 m\\^3 \\(the default dimensions\\), this beam is 0.0271875 m\\^3"
  --threads 1 --quick --width 0.25 --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_beam_quick.json)
tessera_add_refusal_test(refuse_calibrate_beam_softening calibrate
  "--material beam uses the beam's linear softening, got --softening power" --threads 1 --material beam --softening power)
tessera_add_refusal_test(refuse_calibrate_beam_blocks calibrate
  "'300' is not a beam block count" --threads 1 --material beam --blocks 300)

# Goodman-Bray toppling row (issue #40): the simulated critical friction angle within 5 % of the
# limit-equilibrium value the driver computes (34.03 deg). Quick, gravity ramped over 0.2 s: 33.62 deg
# (bracket 33.23-34.01, 5 bisections), -1.2 %, 59 537 steps, 0.3 s on one thread; full: -0.20 %;
# gravity at once (--ramp 0): +3.4 %.
tessera_add_example_test(toppling ARGS --quick --threads 1
  CHECKS "error_rel LESS 0.05" "error_rel GREATER -0.05" "reference_critical_friction_deg GREATER 34.0"
         "reference_critical_friction_deg LESS 34.1")
# Housner's rocking block (issue #40). Between impacts the block turns about a rigid edge: the first
# impact at acosh(alpha / (alpha - theta0)) / p = 0.3118 s within 1 % (quick +0.18 %; +0.11 .. +0.18 %
# for k_n 1e7 .. 1e11). The restitution r is that of an elastic penalty impact, not Housner's plastic
# one: over k_n 1e7 .. 1e11, tolerance 0.05 .. 1 mm and base pieces its error spans -0.9 % .. +8.5 %
# (quick: 0.9544 against 0.9118, +4.7 %), so the check is that band, r < 1 (each impact loses
# energy), 4 impacts in 2.5 s and the energy balance (quick 1.2e-4).
tessera_add_example_test(rocking ARGS --quick --threads 1
  CHECKS "first_impact_error_rel LESS 0.01" "first_impact_error_rel GREATER -0.01" "error_rel GREATER -0.02"
         "error_rel LESS 0.10" "restitution LESS 1" "impacts GREATER 3" "energy_error_rel LESS 1e-3")

# ---- brazilian: splitting test of a Voronoi disc (issue #40). Seeds 1-5 (full, 2 nm per step) give
# f_sp / f_T 2.19-3.58 (two seeds not split by 0.3 mm); quick seed 1 (5 nm per step) 2.30. The band
# holds the model where it is (well above EC2's 1.11, docs/validation.md says why); quasi-static:
# top and bottom reactions within 5 % at the peak; the split is found; energy balance.
tessera_add_example_test(brazilian
  ARGS --quick --threads 1
  CHECKS "f_sp_over_f_T GREATER 1.8"
         "f_sp_over_f_T LESS 3.0"
         "split STREQUAL ON" "split_by_hinge STREQUAL OFF"
         "bottom_over_top_at_peak_rel LESS 0.05"
         "bottom_over_top_at_peak_rel GREATER -0.05"
         "energy_balance_error_rel LESS 1e-3")
# A disc stopped before it splits (5 um of strip travel) reports no splitting strength: "split" false
# and f_sp null, with its largest load beside it (a run that never reached its event says so).
tessera_add_example_test(brazilian NAME example_brazilian_not_split
  ARGS --quick --threads 1 --max-displacement 5e-6
  CHECKS "split STREQUAL OFF" "largest_load_N GREATER 1000")
add_test(NAME example_brazilian_not_split_has_no_f_sp
         COMMAND ${CMAKE_COMMAND} -E env python3 -c
                 "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if d['f_sp_Pa'] is None and d['peak_load_N'] is None else 1)"
                 ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_brazilian_not_split/summary.json)
set_tests_properties(example_brazilian_not_split_has_no_f_sp PROPERTIES DEPENDS example_brazilian_not_split)
# The beam's concrete in the disc (--material beam, issue #63): rc_beam's law and parameters at the
# 250-block beam's block size (12 blocks) and 30 mm face zoning, f_sp against its f_T = 2.5 MPa.
# Quick seed 1 (measured): splits, f_sp / f_T 2.00 (1.59 at the diametral crack's opening), 3 s of
# CPU; the band holds the model where it is (above EC2's 1.11, as the prism's concrete).
tessera_add_example_test(brazilian NAME example_brazilian_beam_quick
  ARGS --quick --threads 1 --material beam
  CHECKS "material STREQUAL beam"
         "blocks EQUAL 12"
         "zone_edge_m GREATER 0.0299" "zone_edge_m LESS 0.0301"
         "f_T_Pa GREATER 2.49e6" "f_T_Pa LESS 2.51e6"
         "split STREQUAL ON"
         "f_sp_over_f_T GREATER 1.5" "f_sp_over_f_T LESS 2.5"
         "bottom_over_top_at_peak_rel LESS 0.05"
         "bottom_over_top_at_peak_rel GREATER -0.05"
         "energy_balance_error_rel LESS 1e-3")
tessera_add_refusal_test(refuse_brazilian_material brazilian
  "brazilian: --material 'granite' is not a concrete recipe \\(expected prism or beam\\)" --threads 1 --material granite)
# The beam's concrete with --law slip_softening (issue #63) at the compression set that met f_c 35 MPa
# (phi_0 58 deg, phi_res 15 deg, G_II 300 J/m^2), quick seed 1 to 1 mm (measured: splits at 406 um,
# f_sp / f_T 4.09, 4.05 at the diametral crack's opening; the study's law with the same set 2.79; 7 s
# of CPU): the law reaches the disc (its G_II and phi_res in summary.json) and splitting stays above
# EC2's 1.11 (docs/validation.md "One concrete").
tessera_add_example_test(brazilian NAME example_brazilian_slip_softening_quick
  ARGS --quick --threads 1 --material beam --law slip_softening --phi-deg 58 --phi-res-deg 15 --g-ii 300
       --max-displacement 1e-3
  CHECKS "law STREQUAL slip_softening"
         "g_ii_J_per_m2 EQUAL 300" "phi_res_deg GREATER 14.99" "phi_res_deg LESS 15.01"
         "split STREQUAL ON"
         "f_sp_over_f_T GREATER 3" "f_sp_over_f_T LESS 5"
         "bottom_over_top_at_peak_rel LESS 0.05"
         "bottom_over_top_at_peak_rel GREATER -0.05"
         "energy_balance_error_rel LESS 1e-3")
# --law and --g-ii as compression has them (issue #63): the flags' refusals name the value, the law is
# validated before the scene is built (a G_II below the elastic unloading's is refused).
tessera_add_refusal_test(refuse_brazilian_g_ii_study brazilian
  "brazilian: --g-ii 100 J/m.2 applies to --law slip_softening, crushing or mixed_mode only" --threads 1 --material beam --g-ii 100)
tessera_add_refusal_test(refuse_brazilian_law brazilian
  "brazilian: --law: invalid value 'soft' \\(expected study, slip_softening, crushing or mixed_mode\\)" --threads 1
  --material beam --law soft)
tessera_add_refusal_test(refuse_brazilian_law_prism brazilian
  "brazilian: --law slip_softening applies to --material beam only" --threads 1 --law slip_softening)
tessera_add_refusal_test(refuse_brazilian_g_ii_small brazilian
  "G_II = 10 J/m.2 gives s_u .* G_II must exceed" --threads 1 --material beam --law slip_softening --g-ii 10)
# brazilian --law mixed_mode (law/mixed_mode.hpp, one damage for tension and shear; issue #63's second
# family): the beam's concrete, quick seed 1 (measured: splits at 252 um, f_sp / f_T 1.982, 1.788 at
# the crack's opening; the study's law 1.996; 4 s of CPU). Checks: the law and its default G_II =
# (c_0 / f_T) G_f = 120 J/m^2 reach the disc; the split; the figure within 2 % of the measured one.
tessera_add_example_test(brazilian NAME example_brazilian_mixed_mode_quick
  ARGS --quick --threads 1 --material beam --law mixed_mode
  CHECKS "law STREQUAL mixed_mode"
         "g_ii_J_per_m2 EQUAL 120"
         "split STREQUAL ON"
         "f_sp_over_f_T GREATER 1.94" "f_sp_over_f_T LESS 2.03"
         "energy_balance_error_rel LESS 1e-3")
# The split of halves that turn apart about a chain beside a strip (disc.hpp: once the load has fallen to
# 0.9 of its largest, no intact chain across the middle third): mixed mode G_II 70, 38 blocks, seed 3
# (measured: split at 297.4 um with the load at 48.6 kN, down from 54.4 kN; the middle two thirds alone
# find it at 410.4 um; f_sp / f_T 1.539 either way, 12 s of CPU). Checks the earlier split and the figure
# within 2 %.
tessera_add_example_test(brazilian NAME example_brazilian_hinge_split
  ARGS --quick --threads 1 --material beam --law mixed_mode --g-ii 70 --blocks 38 --seed 3 --max-displacement 1e-3
  CHECKS "split STREQUAL ON" "split_by_hinge STREQUAL ON"
         "split_displacement_m LESS 3.5e-4" "split_displacement_m GREATER 2.5e-4"
         "f_sp_over_f_T GREATER 1.508" "f_sp_over_f_T LESS 1.570"
         "energy_balance_error_rel LESS 1e-3")
tessera_add_refusal_test(refuse_brazilian_mixed_prism brazilian
  "brazilian: --law mixed_mode applies to --material beam only" --threads 1 --law mixed_mode)
tessera_add_refusal_test(refuse_brazilian_mixed_g_ii_small brazilian
  "G_II = 10 J/m.2 gives s_u .* G_II must exceed" --threads 1 --material beam --law mixed_mode --g-ii 10)
tessera_add_refusal_test(refuse_brazilian_phi_res brazilian
  "brazilian: --phi-deg 35 must not be below the residual 40 deg" --threads 1 --material beam --phi-res-deg 40)

# ---- rc_beam's law options and bars that cannot yield (issue #41 items 1-3): the quick beam with
# --cohesion coupled (presets::coupled_beam_law), --slip-breaks-tension and --steel-yield 1e12
# (14 s on one thread). Checks: the options recorded; the hand yield load A_s f_y z follows f_y
# (52.96 kN x 1e12 / 440e6 = 120.36 MN); the bars stay elastic; a vertical crack first; the law
# reaches the run: the peak of this short run is 23.14 kN against 22.91 kN with the study's law
# (measured); the shear across three sections of the shear span at the peak (beam_shear.hpp: the
# sub-contacts and trusses crossing them) adds up to the support reaction P/2 within 15 %
# (measured 8.1 %; the rest is the local damping's drag and the inertia of the mass-scaled run);
# energy balance.
tessera_add_example_test(rc_beam NAME example_rc_beam_law_options_quick
  ARGS --quick --threads 1 --no-vtk --cohesion coupled --slip-breaks-tension --steel-yield 1e12
  FILES curve.csv
  CHECKS "cohesion STREQUAL coupled"
         "slip_breaks_tension STREQUAL ON"
         "steel_yield_Pa GREATER 0.99e12"
         "hand_yield_load_N GREATER 1.2030e8"
         "hand_yield_load_N LESS 1.2042e8"
         "steel_yielded STREQUAL OFF"
         "vertical_cracks_first STREQUAL ON"
         "peak_load_N GREATER 23.0e3"
         "peak_load_N LESS 23.3e3"
         "shear_at_peak_closure_error_rel LESS 0.15"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
tessera_add_refusal_test(refuse_rc_beam_cohesion rc_beam "--cohesion: invalid value 'glued'" --threads 1 --cohesion glued)
# The shear figure's beam (issue #63 item 3; docs/studies/one_concrete.md "Shear"): the beam with a
# 100 mm constant-moment zone and bars that cannot yield, its hand values P = 2 V_c from EC2 6.2.a
# without partial factor (0.18 k (100 rho f_c)^(1/3) b d, k = 2: 54.75 kN) and Zsutty's fit for a/d
# >= 2.5 (2.14 (f_c rho d / a)^(1/3) MPa b d: 48.62 kN) with rho = 201 / (200 x 125) and f_c 35 MPa,
# a/d = 3. The quick run stops soon after first cracking (measured: 32.08 kN at 0.27 mm, the first
# crack at 10.96 kN against the hand 10.98), never at the 25 % load drop that is the failure: it
# says so (failure_reached false) and reports no peak ratios (null), only the highest load it carried,
# which lies between the hand first cracking and Zsutty's shear capacity.
tessera_add_example_test(rc_beam NAME example_rc_beam_shear_hand_quick
  ARGS --quick --threads 1 --no-vtk --moment-zone 0.1 --steel-yield 1e12
  CHECKS "hand_ec2_shear_load_N GREATER 54.70e3" "hand_ec2_shear_load_N LESS 54.80e3"
         "hand_zsutty_shear_load_N GREATER 48.57e3" "hand_zsutty_shear_load_N LESS 48.67e3"
         "shear_span_over_depth GREATER 2.999" "shear_span_over_depth LESS 3.001"
         "failure_reached STREQUAL OFF" "peak_over_ec2_shear IS NULL" "peak_over_zsutty_shear IS NULL"
         "peak_over_shear_reference IS NULL" "peak_load_N GREATER 10.98e3" "peak_load_N LESS 48.62e3"
         "load_at_stop_N GREATER 10.98e3" "steel_yielded STREQUAL OFF"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
tessera_add_refusal_test(refuse_rc_beam_moment_zone rc_beam
  "plate length 0.05 m must be below twice the overhang .* and the constant-moment zone \\(0.04 m\\)" --threads 1
  --moment-zone 0.04)
tessera_add_refusal_test(refuse_rc_beam_coupled_elastic rc_beam
  "--cohesion coupled is built with --compression plastic only" --threads 1 --quick --cohesion coupled --compression elastic)
tessera_add_refusal_test(refuse_rc_beam_steel_yield rc_beam "--steel-yield: value '0' must be > 0" --threads 1 --steel-yield 0)
# --failure-crack diagonal (examples/rc_beam/beam_failure_rule.hpp): the 60-block shear beam's seed 2
# with the mixed-mode law falls 25 % below a 25.24 kN peak at 0.89 mm, at its first flexural cracks,
# where the default rule stops it; judged by what broke (no inclined crack opened since the peak, and
# the band that softened lies in the constant-moment zone) it is a dip, and the run goes on to the
# 1.2 mm stop, the load past the dip's peak (27.85 kN; 40 s of CPU).
tessera_add_example_test(rc_beam NAME example_rc_beam_failure_crack_dip
  ARGS --threads 1 --no-vtk --steel-yield 1e12 --zone-edge 0.05 --rate 0.01 --blocks 60 --law mixed_mode --g-ii 70
       --seed 2 --failure-crack diagonal --max-deflection 0.0012
  CHECKS "failure_crack STREQUAL diagonal" "failure_reached STREQUAL OFF" "failure_deflection_m IS NULL"
         "dip_deflections_m MATCHES ^[^,]*0[.]000[89][0-9]*[^,]*$" "end_deflection_m GREATER 1.19e-3"
         "peak_load_N GREATER 25.3e3" "peak_deflection_m GREATER 1.0e-3"
  TIMEOUT 900)
tessera_add_refusal_test(refuse_calibrate_shear_failure_crack calibrate "--shear-failure-crack: invalid value 'diag'"
  --targets shear --shear-failure-crack diag)
tessera_add_refusal_test(refuse_rc_beam_failure_crack rc_beam "--failure-crack: invalid value 'shear'" --threads 1
  --failure-crack shear)
tessera_add_refusal_test(refuse_rc_beam_failure_crack_confirm rc_beam
  "rc_beam: --failure-crack diagonal runs in one process without --failure-confirm \\(got 0.0002 m, 1 ranks\\)"
  --threads 1 --failure-crack diagonal --failure-confirm 2e-4)
tessera_add_refusal_test(refuse_rc_beam_steel_yield_nan rc_beam "--steel-yield: invalid value 'nan'" --threads 1 --steel-yield nan)
# rc_beam --law slip_softening (issue #63 items 3 and 6, examples/rc_beam/beam_law.hpp): the quick
# beam with the slip-softening set of the compression meeting (phi_0 58 deg, phi_res 15 deg, G_II
# 300 J/m^2, cap 100 MPa), 77 s of CPU on one thread beside other jobs. Checks: the law and its set
# recorded, s_u = 2 G_II / (c_0 - c_res) = 600 / 4.95e6 = 0.1212 mm; the plates keep the study's
# 35 deg and the hand values the concrete's f_c = 35 MPa (EC2 54.75 kN, not the cap's 100 MPa);
# in tension the two laws are one law, so first cracking is the study law's 14.11 kN within 1 %
# (measured 14.14 kN); the law reaches the run: the peak of this short run is 22.95 kN against the
# study law's 22.91 kN (measured); energy balance.
tessera_add_example_test(rc_beam NAME example_rc_beam_slip_softening_quick
  ARGS --quick --threads 1 --no-vtk --law slip_softening --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6
  FILES curve.csv
  CHECKS "law STREQUAL slip_softening"
         "g_ii_J_per_m2 EQUAL 300"
         "phi_0_deg GREATER 57.99" "phi_0_deg LESS 58.01"
         "phi_res_deg GREATER 14.99" "phi_res_deg LESS 15.01"
         "cap_Pa GREATER 99.9e6" "cap_Pa LESS 100.1e6"
         "plate_friction_deg GREATER 34.99" "plate_friction_deg LESS 35.01"
         "hand_ec2_shear_load_N GREATER 54.70e3" "hand_ec2_shear_load_N LESS 54.80e3"
         "vertical_cracks_first STREQUAL ON"
         "softening_slip_m GREATER 1.2120e-4" "softening_slip_m LESS 1.2123e-4"
         "first_crack_load_N GREATER 13.97e3" "first_crack_load_N LESS 14.25e3"
         "peak_load_N GREATER 22.93e3" "peak_load_N LESS 22.97e3"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
# rc_beam --law mixed_mode (law/mixed_mode.hpp; issue #63's second family): the quick beam, 17-20 s of
# CPU. Checks: the law and its default G_II = (c_0 / f_T) G_f = 120 J/m^2 with l_II = 2 G_II / c_0 =
# 48 um recorded; first cracking near the study law's 14.11 kN (measured 14.57 kN: the faces that
# open and slide at once crack on the ellipse); the peak of this short run (measured 23.36 kN at
# a629f53, 23.45 kN at acc3bbc: the rounding of tan phi_0 moves it by 0.4 %), within 1 %; energy balance.
tessera_add_example_test(rc_beam NAME example_rc_beam_mixed_mode_quick
  ARGS --quick --threads 1 --no-vtk --law mixed_mode
  CHECKS "law STREQUAL mixed_mode"
         "g_ii_J_per_m2 EQUAL 120"
         "softening_slip_m GREATER 4.79e-5" "softening_slip_m LESS 4.81e-5"
         "first_crack_load_N GREATER 14.42e3" "first_crack_load_N LESS 14.71e3"
         "peak_load_N GREATER 23.12e3" "peak_load_N LESS 23.68e3"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
# --cohesion-ratio 1 (c_0 = f_T, beam_law.hpp add_beam_law_flags): the default G_II follows c_0
# ((c_0 / f_T) G_f = 60 J/m^2, l_II = 2 G_II / c_0 = 48 um again), the contacts get c_0 = 2.5 MPa, and
# this short run's peak (measured 22.51 kN at ac54d3b, against 23.45 kN with c_0 = 2 f_T)
# within 1 %.
tessera_add_example_test(rc_beam NAME example_rc_beam_mixed_mode_cohesion_quick
  ARGS --quick --threads 1 --no-vtk --law mixed_mode --cohesion-ratio 1
  CHECKS "law STREQUAL mixed_mode"
         "g_ii_J_per_m2 EQUAL 60"
         "contact_c_0_Pa GREATER 2.499e6" "contact_c_0_Pa LESS 2.501e6"
         "softening_slip_m GREATER 4.79e-5" "softening_slip_m LESS 4.81e-5"
         "peak_load_N GREATER 22.28e3" "peak_load_N LESS 22.74e3"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
tessera_add_refusal_test(refuse_rc_beam_cohesion_ratio rc_beam
  "--cohesion-ratio: value '0.05' must be >= 0.1" --threads 1 --cohesion-ratio 0.05)
tessera_add_refusal_test(refuse_rc_beam_cohesion_params rc_beam
  "rc_beam: --cohesion-ratio with --params calibrated.json: the file sets the concrete \\(drop the flag\\)"
  --threads 1 --cohesion-ratio 1 --params calibrated.json)
tessera_add_refusal_test(refuse_rc_beam_g_ii_study rc_beam
  "rc_beam: --g-ii 100 J/m.2 applies to --law slip_softening, crushing or mixed_mode only" --threads 1 --g-ii 100)
tessera_add_refusal_test(refuse_rc_beam_g_ii_small rc_beam
  "G_II = 10 J/m.2 gives s_u .* G_II must exceed" --threads 1 --law slip_softening --g-ii 10)
tessera_add_refusal_test(refuse_rc_beam_law rc_beam
  "--law: invalid value 'soft' \\(expected study or slip_softening or crushing or mixed_mode\\)" --threads 1 --law soft)
tessera_add_refusal_test(refuse_rc_beam_phi_res rc_beam
  "rc_beam: --phi-res-deg 40 must not exceed --phi-deg 35" --threads 1 --phi-res-deg 40)
tessera_add_refusal_test(refuse_rc_beam_cap_elastic rc_beam
  "rc_beam: --cap 100000000 Pa applies to --compression plastic" --threads 1 --compression elastic --cap 100e6)
tessera_add_refusal_test(refuse_rc_beam_slip_coupled rc_beam
  "rc_beam: --law slip_softening is built with --compression plastic, --cohesion decoupled .*got .*--cohesion coupled"
  --threads 1 --law slip_softening --cohesion coupled)
tessera_add_refusal_test(refuse_rc_beam_mixed_coupled rc_beam
  "rc_beam: --law mixed_mode is built with --compression plastic, --cohesion decoupled .*got .*--cohesion coupled"
  --threads 1 --law mixed_mode --cohesion coupled)
tessera_add_refusal_test(refuse_rc_beam_mixed_g_ii_small rc_beam
  "G_II = 30 J/m.2 gives s_u .* G_II must exceed" --threads 1 --law mixed_mode --g-ii 30)
tessera_add_refusal_test(refuse_rc_beam_slip_breaks_tension rc_beam
  "rc_beam: --law slip_softening is built .*got .*--slip-breaks-tension" --threads 1 --law slip_softening
  --slip-breaks-tension)
tessera_add_refusal_test(refuse_rc_beam_slip_relaxation rc_beam
  "--scheme relaxation is built for the study's law .*got --law slip_softening" --quick --scheme relaxation
  --law slip_softening)
tessera_add_refusal_test(refuse_rc_beam_slip_params rc_beam
  "rc_beam: --law with --params calibrated.json: the file sets the concrete \\(drop the flag\\)" --threads 1
  --law slip_softening --params calibrated.json)
# rc_beam --params with a slip-softening entry (issue #63): the file's whole concrete (law, scales,
# c_0/f_T, phi_0, phi_res, G_II, cap; beam_law.hpp load_beam_params, through concrete_set.hpp). The
# quick beam's recipe (60 blocks, 50 mm zoning) with the compression set in
# tests/data/concrete_beam_slip_quick.json runs exactly the beam of the five flags: the same
# curve.csv bits as example_rc_beam_slip_softening_quick (measured). A file of another recipe
# (concrete_beam_slip.json: 250 blocks, 30 mm) is refused, naming both zoning edges.
tessera_add_example_test(rc_beam NAME example_rc_beam_params_slip_quick
  ARGS --quick --threads 1 --no-vtk --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_slip_quick.json
  FILES curve.csv
  CHECKS "parameters STREQUAL calibrated" "law STREQUAL slip_softening" "g_ii_J_per_m2 EQUAL 300"
         "phi_0_deg GREATER 57.99" "phi_0_deg LESS 58.01" "phi_res_deg GREATER 14.99" "phi_res_deg LESS 15.01"
         "cap_Pa EQUAL 100000000" "contact_c_0_Pa EQUAL 5000000"
  TIMEOUT 600)
# tessera_add_same_curve_test(NAME A B): NAME passes when example tests A and B wrote the same
# curve.csv bits (A and B run first, as its fixture).
function(tessera_add_same_curve_test name a b)
  if(TEST ${a} AND TEST ${b})
    set_tests_properties(${a} ${b} PROPERTIES FIXTURES_SETUP ${name}_pair)
    add_test(NAME ${name} COMMAND ${CMAKE_COMMAND} -E compare_files
             ${CMAKE_CURRENT_BINARY_DIR}/example_out/${a}/curve.csv ${CMAKE_CURRENT_BINARY_DIR}/example_out/${b}/curve.csv)
    set_tests_properties(${name} PROPERTIES FIXTURES_REQUIRED ${name}_pair LABELS example)
  endif()
endfunction()
tessera_add_same_curve_test(example_rc_beam_params_slip_same_bits example_rc_beam_params_slip_quick
                            example_rc_beam_slip_softening_quick)
tessera_add_refusal_test(refuse_rc_beam_params_slip_zoning rc_beam
  "concrete_beam_slip.json was fitted with a face zoning edge of 0.03 m, this run uses 0.05 m"
  --threads 1 --quick --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_slip.json)
tessera_add_refusal_test(refuse_rc_beam_params_flag rc_beam
  "rc_beam: --phi-deg with --params .*: the file sets the concrete"
  --threads 1 --quick --phi-deg 40 --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_slip_quick.json)
# ---- direct_tension --material beam (issue #63 item 6; direct_tension/concrete.hpp): the beam's
# concrete on calibrate's beam-recipe prism with any law, the run of calibrate --targets tension.
# The quick beam recipe (60 blocks, 50 mm zoning: a 37-block 150 x 150 x 600 mm prism) with the mixed-
# mode set the beam runs with (G_II 70 J/m^2). Measured (quick, seed 1): peak 2.342 MPa = 0.937 f_T
# (f_T = 2.5 MPa), the same bits as calibrate --targets tension --quick --material beam --law mixed_mode
# --g-ii 70 --iterations 0 (seed 1's tension value); 14 500 steps. The checks: the law and G_II reach the
# contacts, the peak within 0.5 % of the measured one. The same run from tests/data/concrete_beam_mixed_quick.json
# (--params: the file's whole concrete) writes the same curve.csv bits.
tessera_add_example_test(direct_tension NAME example_direct_tension_beam_mixed_quick
  ARGS --quick --threads 1 --material beam --recipe-blocks 60 --zone-edge 0.05 --law mixed_mode --g-ii 70
  FILES curve.csv contacts_peak.vtp zones_peak.vtu
  CHECKS "material STREQUAL beam" "law STREQUAL mixed_mode" "g_ii_J_per_m2 EQUAL 70" "recipe_blocks EQUAL 60"
         "f_T_Pa EQUAL 2500000" "peak_stress_Pa GREATER 2.330e6" "peak_stress_Pa LESS 2.354e6"
         "energy_balance_error_rel LESS 0.01"
  TIMEOUT 300)
tessera_add_example_test(direct_tension NAME example_direct_tension_beam_params_quick
  ARGS --quick --threads 1 --material beam --recipe-blocks 60 --zone-edge 0.05
       --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_quick.json
  FILES curve.csv
  CHECKS "law STREQUAL mixed_mode" "g_ii_J_per_m2 EQUAL 70"
  TIMEOUT 300)
tessera_add_same_curve_test(example_direct_tension_beam_params_same_bits example_direct_tension_beam_params_quick
                            example_direct_tension_beam_mixed_quick)
# The same prism and set pulled to separation (not --quick, which stops at 70 % of the peak; its 5 nm
# step given): the fracture energy of one damage for tension and shear. Measured (seed 1): separated
# at 14 500 steps, the tension dissipated 1.134 J against G_f x the area broken in tension 1.536 J
# (-26.2 %: the 37-block prism stores more elastic energy at its peak than G_f over its section, the
# crack runs through at once and the local damping takes 0.59 J), every contact's dissipation over
# G_f A (energy_over_G_f) 1.039; the study's beam law on this prism dissipates +45.4 % (2.31), so the
# band [-35 %, -15 %] and [0.95, 1.13] tells the laws apart. The beam's own 155-block prism at 2 nm:
# -9.9 / -1.0 / -21.3 % on seeds 1-3 (docs/studies/one_concrete.md, "To separation").
tessera_add_example_test(direct_tension NAME example_direct_tension_beam_mixed_separation
  ARGS --threads 1 --material beam --recipe-blocks 60 --zone-edge 0.05 --law mixed_mode --g-ii 70
       --step-displacement 5e-9
  FILES curve.csv
  CHECKS "separated STREQUAL ON" "fracture_energy_error_rel GREATER -0.35" "fracture_energy_error_rel LESS -0.15"
         "energy_over_G_f GREATER 0.95" "energy_over_G_f LESS 1.13" "energy_balance_error_rel LESS 1e-4"
  TIMEOUT 300)
# Refused, naming the value: a beam-only law on the prism, a G_II below the law's bound (the contacts
# are built before anything is written), a law parameter the law has no use for, a concrete flag beside
# --params, a prism file for the beam's recipe, a prism-only flag with the beam, a prism --blocks off Table 1.
tessera_add_refusal_test(refuse_direct_tension_law_prism direct_tension
  "^direct_tension: --law mixed_mode applies to --material beam only" --threads 1 --law mixed_mode)
tessera_add_refusal_test(refuse_direct_tension_cap_prism direct_tension
  "^direct_tension: --cap 50000000 applies to --material beam only" --threads 1 --cap 50e6)
tessera_add_refusal_test(refuse_direct_tension_mixed_g_ii_small direct_tension
  "G_II = 10 J/m.2 gives s_u .* G_II must exceed" --threads 1 --material beam --law mixed_mode --g-ii 10)
tessera_add_refusal_test(refuse_direct_tension_g_ii_study direct_tension
  "^direct_tension: --g-ii 100 J/m.2 applies to --law slip_softening, crushing or mixed_mode only" --threads 1
  --material beam --g-ii 100)
tessera_add_refusal_test(refuse_direct_tension_beam_params_flag direct_tension
  "^direct_tension: --law with --params .*: the file sets the concrete \\(drop the flag\\)" --threads 1
  --material beam --law mixed_mode --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_quick.json)
tessera_add_refusal_test(refuse_direct_tension_beam_prism_file direct_tension
  "calibrated_quick.json was fitted on the prism recipe, this run needs the beam recipe" --threads 1 --quick
  --material beam --params ${PROJECT_SOURCE_DIR}/tests/data/calibrated_quick.json)
tessera_add_refusal_test(refuse_direct_tension_beam_zoning direct_tension
  "concrete_beam_mixed_quick.json was fitted with a face zoning edge of 0.05 m, this run uses 0.03 m" --threads 1
  --quick --material beam --recipe-blocks 60 --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_quick.json)
tessera_add_refusal_test(refuse_direct_tension_beam_softening direct_tension
  "^direct_tension: --softening applies to --material prism only" --threads 1 --material beam --softening linear)
tessera_add_refusal_test(refuse_direct_tension_blocks_table direct_tension
  "^direct_tension: --blocks 120 must be 100, 250, 500 or 750 with --material prism" --threads 1 --blocks 120)
# ---- rc_beam --span full (issue #41 item 3): the whole beam, 120 blocks (--blocks 60 per half
# span), both supports and loading plates, the plates on a spreader (equal loads), held in x at
# mid-span (examples/rc_beam/beam_span.hpp); 28 s of CPU on one thread. Checks, in the elastic
# stage (beam_span.hpp's window: deflections of 0.06-0.18 mm, around half the hand first-cracking
# deflection, 0.122 mm):
#   - the load at 0.122 mm against the half model's (the default quick test above pins it at
#     8115 N): 7883 N, -2.9 % (measured). Tolerance -15 % / +5 %: the full beam's blocks are another
#     tessellation, and the half model's own value moves by 10 % between seeds (8115, 8933, 8408 N
#     for seeds 1-3); and the full beam is softer on the whole (seeds 1-3: 7883, 7789, 7232 N, -2.9,
#     -12.8, -14.0 % against the half model of the same seed). A likely cause, not measured apart:
#     the half model's symmetry face is a plane without joints (mirrored, its cells at mid-span
#     merge with their twins), a joint row fewer in the constant-moment zone. A load or deflection
#     read for one span only (P = one reaction) misses the band by a factor near 2.
#   - symmetry: the two support reactions over the window, (R_left - R_right) / (R_left + R_right),
#     within 3 % (measured 1.1 %; seeds 2, 3: 0.4, 0.7 %): with equal plate loads statics asks 0,
#     the rest is the local damping's drag and the inertia of the mass-scaled run (a pin at the
#     left support instead of mid-span gave 6.2 %); the two loading plates' loads within 1 %
#     (measured 0.3 %; seeds 2, 3: -0.1, 0.07 %: the spreader);
#   - each plate touches the beam; the first crack vertical and in the constant-moment zone; the
#     energy balance with four plates.
tessera_add_example_test(rc_beam NAME example_rc_beam_span_full_quick
  ARGS --quick --threads 1 --no-vtk --span full
  FILES curve.csv cracks.csv
  CHECKS "span STREQUAL full"
         "model_blocks EQUAL 120"
         "support_plate_subcontacts GREATER 20"
         "loading_plate_subcontacts GREATER 20"
         "right_support_plate_subcontacts GREATER 20"
         "right_loading_plate_subcontacts GREATER 20"
         "elastic_check_load_N GREATER 6.90e3"
         "elastic_check_load_N LESS 8.52e3"
         "elastic_check_reaction_asymmetry_rel LESS 0.03"
         "elastic_check_reaction_asymmetry_rel GREATER -0.03"
         "elastic_check_plate_load_asymmetry_rel LESS 0.01"
         "elastic_check_plate_load_asymmetry_rel GREATER -0.01"
         "first_crack_in_moment_zone STREQUAL ON"
         "vertical_cracks_first STREQUAL ON"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 900)
tessera_add_refusal_test(refuse_rc_beam_span rc_beam "--span: invalid value 'quarter'" --threads 1 --span quarter)

# ---- the drivers under mpirun (issue #44 items 4 and 7): the quick prism, tie and beam split over
# 2 and 3 ranks (METIS's cut where built in, one thread a rank) write one process's curve.csv
# (and end-of-run VTK snapshots, the beam's crack list) byte for byte (tests/check_split_run.cmake
# runs them). Each driver's one-process run is made once, by the fixture test example_<ex>_mpi_ref,
# and both split tests compare against it.
if(TESSERA_MPI)
  string(REPLACE ";" "|" split_mpiflags "${tessera_mpiexec_flags}")
  set(split_drivers direct_tension rc_tie rc_beam)
  if(Python3_Interpreter_FOUND)
    list(APPEND split_drivers rubble)
  endif()
  # One set of flags a driver: the reference and its split runs must be run alike.
  foreach(ex IN LISTS split_drivers)
    set(split_args_${ex} "--quick|--threads|1")
    if(ex STREQUAL "rc_beam")
      set(split_args_${ex} "--quick|--threads|1|--no-vtk")
    endif()
    add_test(NAME example_${ex}_mpi_ref
             COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:${ex}> -DNP=1
                     -DOUT=${CMAKE_CURRENT_BINARY_DIR}/example_out/example_${ex}_mpi_ref
                     "-DARGS=${split_args_${ex}}" -P ${CMAKE_CURRENT_LIST_DIR}/check_split_run.cmake)
    set_tests_properties(example_${ex}_mpi_ref PROPERTIES TIMEOUT 900 LABELS "example;mpi"
                         FIXTURES_SETUP ${ex}_mpi_ref ENVIRONMENT "OMP_WAIT_POLICY=PASSIVE")
  endforeach()
  foreach(ranks 2 3)
    foreach(ex direct_tension rc_tie rc_beam)
      if(ex STREQUAL "direct_tension")
        set(same curve.csv|contacts_end.vtp|zones_end.vtu)
      elseif(ex STREQUAL "rc_tie")
        set(same curve.csv|end_contacts.vtp|end_zones.vtu|end_bar.vtp)
      else()
        # The beam's steel plates are rigid platens (applied forces), their gridpoints shared
        # every step (split_run::share_rows).
        set(same curve.csv|cracks.csv)
      endif()
      add_test(NAME example_${ex}_mpi_${ranks}
               COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:${ex}> -DMPIEXEC=${MPIEXEC_EXECUTABLE} -DNP=${ranks}
                       "-DMPIFLAGS=${split_mpiflags}" -DOUT=${CMAKE_CURRENT_BINARY_DIR}/example_out/example_${ex}_mpi_${ranks}
                       -DONE=${CMAKE_CURRENT_BINARY_DIR}/example_out/example_${ex}_mpi_ref
                       "-DARGS=${split_args_${ex}}" "-DSAME=${same}" -P ${CMAKE_CURRENT_LIST_DIR}/check_split_run.cmake)
      # About 10-30 s alone; the timeout leaves room for a machine doing other work.
      set_tests_properties(example_${ex}_mpi_${ranks} PROPERTIES TIMEOUT 900 PROCESSORS ${ranks} LABELS "example;mpi"
                           FIXTURES_REQUIRED ${ex}_mpi_ref
                           ENVIRONMENT "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMP_WAIT_POLICY=PASSIVE")
    endforeach()
    # The quick rubble (issue #44 item 5): rigid blocks on detected contacts, split by blocks
    # (distributed::rigid_stepper). The VTK snapshots (every gridpoint) are one process's bytes;
    # curve.csv too, but for the rebuild exchange, a book each rank sums over its own contacts.
    if(Python3_Interpreter_FOUND)
      add_test(NAME example_rubble_mpi_${ranks}
               COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:rubble> -DMPIEXEC=${MPIEXEC_EXECUTABLE} -DNP=${ranks}
                       "-DMPIFLAGS=${split_mpiflags}" -DOUT=${CMAKE_CURRENT_BINARY_DIR}/example_out/example_rubble_mpi_${ranks}
                       -DONE=${CMAKE_CURRENT_BINARY_DIR}/example_out/example_rubble_mpi_ref
                       "-DARGS=${split_args_rubble}" "-DSAME=blocks_0010.vtu|blocks_0020.vtu"
                       -DPYTHON=${Python3_EXECUTABLE} -DBOOKS_FILE=curve.csv -DBOOKS=rebuild_exchange_J
                       -P ${CMAKE_CURRENT_LIST_DIR}/check_split_run.cmake)
      set_tests_properties(example_rubble_mpi_${ranks} PROPERTIES TIMEOUT 900 PROCESSORS ${ranks} LABELS "example;mpi"
                           FIXTURES_REQUIRED rubble_mpi_ref
                           ENVIRONMENT "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMP_WAIT_POLICY=PASSIVE")
    endif()
  endforeach()
endif()

# ---- compression: a 100 x 100 x 200 mm prism of the beam's concrete (23 blocks at the beam's block
# size) between frictionless ends, 5 nm per step, to 10 % past the peak. Checks: a peak is found (the
# stress fell after it); the elastic figures of the recipe: E 15-30 GPa (the contacts in series with
# the 10 E blocks give about 21 GPa in the cylinder, against the beam's 25) and nu 0.1-0.3 (0.2);
# the strength where the study's law puts it, f_c 10-30 MPa (the cylinder: 17.4 MPa at 61 blocks; a
# single facet sliding under uniaxial stress gives 2 c_0 cos(phi) / (1 - sin(phi)) = 19.2 MPa), i.e.
# well below the 35 MPa reference (docs/validation.md "One concrete"); quasi-static; energy balance.
# Checks of both materials' quick runs: a peak, the strength band, quasi-static, energy balance.
set(compression_quick_checks "peak STREQUAL ON" "poisson GREATER 0.1" "poisson LESS 0.3" "f_c_Pa GREATER 10e6"
    "f_c_Pa LESS 30e6" "quasi_static_index LESS 0.05" "energy_balance_error_rel LESS 1e-3")
tessera_add_example_test(compression
  ARGS --quick --threads 1 --shape prism --diameter 0.1 --height 0.2
  FILES curve.csv end_zones.vtu end_contacts.vtp compression.pvd
  CHECKS ${compression_quick_checks}
         "blocks EQUAL 23"
         "young_Pa GREATER 15e9" "young_Pa LESS 30e9"
         "peak_strain GREATER 3e-4"
  TIMEOUT 900)
tessera_add_refusal_test(refuse_compression_ends compression
  "--ends: invalid value 'glued' \\(expected fixed or frictionless or friction\\)" --threads 1 --ends glued)
tessera_add_refusal_test(refuse_compression_friction_zero compression
  "--friction 0 must be > 0 with --ends friction" --threads 1 --ends friction --friction 0)
tessera_add_refusal_test(refuse_compression_phi_res compression
  "--phi-res-deg 40 must not exceed --phi-deg 35" --threads 1 --phi-res-deg 40)
tessera_add_refusal_test(refuse_compression_not_quasi_static compression
  "is not quasi-static: the end moves .* use a rate <=" --threads 1 --step-displacement 1e-7)
tessera_add_refusal_test(refuse_compression_memory compression
  "would need about .* zones .* GB.*use a smaller specimen or fewer --blocks" --threads 1 --diameter 2 --height 4)
tessera_add_refusal_test(refuse_compression_confinement compression
  "--confinement: value '-1' must be >= 0" --threads 1 --confinement -1)
tessera_add_refusal_test(refuse_compression_g_ii_study compression
  "--g-ii 100 J/m.2 applies to --law slip_softening, crushing or mixed_mode only" --threads 1 --g-ii 100)
tessera_add_refusal_test(refuse_compression_law compression
  "--law: invalid value 'soft' \\(expected study or slip_softening or crushing or mixed_mode\\)" --threads 1 --law soft)
tessera_add_refusal_test(refuse_compression_g_ii_small compression
  "G_II = 10 J/m.2 gives s_u .* G_II must exceed" --threads 1 --law slip_softening --g-ii 10 --shape prism --diameter 0.1 --height 0.2)
# The prism's concrete in compression (--material prism, issue #63): the study's prism law (power
# softening, no contact cap) at the 100-block prism's block size, one zone per face triangle.
# Quick (measured): 72 blocks in the 100 x 100 x 200 mm prism, f_c 17.07 MPa at 0.80e-3 (the single-facet
# bound with c_0 = 2 x 0.907 x 2.15 MPa: 15.0 MPa), E 32.4 GPa, nu 0.18; 9 s of CPU.
tessera_add_example_test(compression NAME example_compression_prism_quick
  ARGS --quick --threads 1 --material prism --shape prism --diameter 0.1 --height 0.2
  FILES curve.csv
  CHECKS ${compression_quick_checks}
         "material STREQUAL prism"
         "blocks EQUAL 72"
         "zone_edge_m LESS 1e-12"
         "f_T_Pa GREATER 1.94e6" "f_T_Pa LESS 1.96e6"
         "young_Pa GREATER 20e9" "young_Pa LESS 45e9"
  TIMEOUT 900)
tessera_add_refusal_test(refuse_compression_material compression
  "--material: invalid value 'granite' \\(expected beam or prism\\)" --threads 1 --material granite)
tessera_add_refusal_test(refuse_compression_cap_prism compression
  "--cap 1e\\+08 applies to --material beam only" --threads 1 --material prism --cap 100e6)
tessera_add_refusal_test(refuse_compression_law_prism compression
  "--law slip_softening applies to --material beam only" --threads 1 --material prism --law slip_softening)
# --law crushing (crushing_beam_law: slip softening and a cap softening with the plastic closure over
# --g-c, law/compression.hpp softening_cap): the 100 x 100 x 200 mm prism between fixed ends with the
# compression set (phi_0 58, phi_res 15, G_II 300, cap 100 MPa) and G_c = 10 kJ/m^2 peaks (measured:
# 55.29 MPa at 2.79e-3, 34 s); with --law slip_softening the same prism has no peak by 5e-3 (84.3 MPa).
tessera_add_example_test(compression NAME example_compression_crushing_quick
  ARGS --quick --threads 1 --no-vtk --shape prism --diameter 0.1 --height 0.2 --max-strain 5e-3 --ends fixed
       --law crushing --g-c 1e4 --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6
  CHECKS "law STREQUAL crushing" "G_c_J_per_m2 EQUAL 10000" "cap_residual GREATER 0.099" "cap_residual LESS 0.101"
         "peak STREQUAL ON" "f_c_Pa GREATER 55.2e6" "f_c_Pa LESS 55.4e6" "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 600)
# --law mixed_mode (law/mixed_mode.hpp: one damage for tension and shear; issue #63) on the same
# prism, frictionless ends, with the compression set: peaks (measured: 36.58 MPa at 1.53e-3, 6 s of
# CPU); checks that the law and its G_II reach the contacts (c_res 0: the law has none) and the peak.
tessera_add_example_test(compression NAME example_compression_mixed_mode_quick
  ARGS --quick --threads 1 --no-vtk --shape prism --diameter 0.1 --height 0.2 --max-strain 5e-3
       --material beam --law mixed_mode --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6
  CHECKS "law STREQUAL mixed_mode" "G_II_J_per_m2 EQUAL 300" "peak STREQUAL ON"
         "f_c_Pa GREATER 36.4e6" "f_c_Pa LESS 36.8e6" "energy_balance_error_rel LESS 1e-3")
# --law mixed_mode --g-c (presets::mixed_crushing_beam_law: the mixed law whose cap softens with
# crushing, law/mixed_mode.hpp) on the same prism between fixed ends, where the mixed law with its
# plastic cap has no peak: peaks (measured: 54.87 MPa at 2.79e-3, 12 s of CPU) and softens to the
# drop; checks that G_c and the residual reach the contacts and the peak. Refused: --cap-residual
# (or --crush-shear) with --law mixed_mode but no --g-c.
tessera_add_example_test(compression NAME example_compression_mixed_crushing_quick
  ARGS --quick --threads 1 --no-vtk --shape prism --diameter 0.1 --height 0.2 --max-strain 3.5e-3 --ends fixed
       --material beam --law mixed_mode --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6 --g-c 1e4
  CHECKS "law STREQUAL mixed_mode" "G_c_J_per_m2 EQUAL 10000" "cap_residual GREATER 0.099" "cap_residual LESS 0.101"
         "G_II_J_per_m2 EQUAL 300" "peak STREQUAL ON" "f_c_Pa GREATER 54.8e6" "f_c_Pa LESS 54.95e6"
         "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 300)
tessera_add_refusal_test(refuse_compression_mixed_cap_residual_no_g_c compression
  "--cap-residual with --law mixed_mode needs --g-c > 0 \\(got --g-c 0" --threads 1 --material beam --law mixed_mode
  --cap-residual 0.2)
tessera_add_refusal_test(refuse_rc_beam_mixed_crush_shear_no_g_c rc_beam
  "rc_beam: --crush-shear with --law mixed_mode needs --g-c > 0" --threads 1 --law mixed_mode --crush-shear)
# Refused, naming the value: the crushing law's flags with another law, a residual outside [0, 1].
tessera_add_refusal_test(refuse_compression_g_c_study compression
  "--g-c applies to --law crushing or mixed_mode only \\(--law study" --threads 1 --g-c 2e4)
tessera_add_refusal_test(refuse_compression_cap_residual compression
  "--cap-residual: value '1.5' must be <= 1" --threads 1 --law crushing --cap-residual 1.5)
# ((1 - 0.1) 35 MPa)^2 / (2 x 500 GPa/m) = 992 J/m^2 (the 23-block prism's k_n is the recipe's to 1 %)
tessera_add_refusal_test(refuse_compression_g_c_small compression
  "compressive fracture energy too small for the law: G_c = 500 J/m.2 must exceed" --threads 1 --law crushing
  --g-c 500 --shape prism --diameter 0.1 --height 0.2)

# ---- --law crushing beyond compression (issue #63): brazilian, rc_beam, calibrated.json and calibrate
# --targets take the crushing law with --g-c, --cap-residual and --crush-shear as compression does.
# The quick disc with the compression set (phi_0 58, phi_res 15, G_II 300, cap 100 MPa, G_c 10 kJ/m^2),
# seed 1 to 1 mm (6 s): before its peak no contact reaches the softening cap, so P_max and f_sp / f_T
# are the slip-softening law's to the bit (3.831, measured); after it the load falls fast: the split is
# found at 366.6 um under 62.01 kN, 0.46 of P_max (the middle third without a chain once the load has
# fallen to 0.9 of its largest; the middle two thirds alone found it at 453 um under 28.35 kN, where
# --law slip_softening still carried 82.56 kN at 477 um: docs/studies/one_concrete.md).
tessera_add_example_test(brazilian NAME example_brazilian_crushing_quick
  ARGS --quick --threads 1 --material beam --law crushing --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6
       --g-c 1e4 --max-displacement 1e-3
  CHECKS "law STREQUAL crushing" "G_c_J_per_m2 EQUAL 10000" "cap_residual GREATER 0.099" "cap_residual LESS 0.101"
         "g_ii_J_per_m2 EQUAL 300" "split STREQUAL ON" "f_sp_over_f_T GREATER 3.826" "f_sp_over_f_T LESS 3.836"
         "split_load_N LESS 65e3" "split_displacement_m LESS 3.8e-4" "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 300)
tessera_add_refusal_test(refuse_brazilian_g_c_study brazilian
  "brazilian: --g-c applies to --law crushing or mixed_mode only \\(--law slip_softening" --threads 1 --material beam
  --law slip_softening --g-c 1e4)
tessera_add_refusal_test(refuse_brazilian_cap_residual brazilian
  "brazilian: --cap-residual = '1.5' must be a number in \\[0, 1\\]" --threads 1 --material beam --law crushing
  --cap-residual 1.5)
# The quick beam with the crushing law to 0.4 mm (15 s of CPU): in tension the law is the slip-softening
# law (first crack 14.14 kN, as example_rc_beam_slip_softening_quick), the law's set is recorded; the
# same beam from tests/data/concrete_beam_crushing_quick.json (--params) writes the same curve.csv bits
# (measured). Refused: a crushing flag with another law, a G_c below the law's bound for the cap, a
# file entry of law crushing without G_c, with a residual outside [0, 1], G_c in a slip-softening entry.
tessera_add_example_test(rc_beam NAME example_rc_beam_crushing_quick
  ARGS --quick --threads 1 --no-vtk --law crushing --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6 --g-c 1e4
       --max-deflection 4e-4
  FILES curve.csv
  CHECKS "law STREQUAL crushing" "G_c_J_per_m2 EQUAL 10000" "cap_residual GREATER 0.099" "cap_residual LESS 0.101"
         "crush_shear STREQUAL OFF" "g_ii_J_per_m2 EQUAL 300" "cap_Pa EQUAL 100000000"
         "first_crack_load_N GREATER 14.13e3" "first_crack_load_N LESS 14.15e3" "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 300)
tessera_add_example_test(rc_beam NAME example_rc_beam_params_crushing_quick
  ARGS --quick --threads 1 --no-vtk --max-deflection 4e-4
       --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_crushing_quick.json
  FILES curve.csv
  CHECKS "parameters STREQUAL calibrated" "law STREQUAL crushing" "G_c_J_per_m2 EQUAL 10000" "phi_0_deg GREATER 57.99"
         "phi_0_deg LESS 58.01"
  TIMEOUT 300)
tessera_add_same_curve_test(example_rc_beam_params_crushing_same_bits example_rc_beam_params_crushing_quick
                            example_rc_beam_crushing_quick)
tessera_add_refusal_test(refuse_rc_beam_crush_shear_study rc_beam
  "rc_beam: --crush-shear applies to --law crushing or mixed_mode only \\(--law study" --threads 1 --crush-shear)
tessera_add_refusal_test(refuse_rc_beam_g_c_small rc_beam
  "compressive fracture energy too small for the law: G_c = 100 J/m.2 must exceed" --threads 1 --law crushing --g-c 100)
tessera_add_refusal_test(refuse_rc_beam_params_no_g_c rc_beam
  "concrete_beam_crushing_no_gc.json: entries\\[0\\]: law crushing needs \"G_c_J_per_m2\""
  --threads 1 --quick --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_crushing_no_gc.json)
tessera_add_refusal_test(refuse_compression_params_cap_residual compression
  "entries\\[0\\].cap_residual = 1.5 must lie in \\[0, 1\\]" --threads 1 --zone-edge 0.05 --recipe-blocks 60
  --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_crushing_bad_residual.json)
tessera_add_refusal_test(refuse_brazilian_recipe_blocks_small brazilian
  "brazilian: --recipe-blocks 5 must be 0 \\(the material's\\) or >= 8 \\(calibrate's and rc_beam's smallest" --threads 1 --recipe-blocks 5)
tessera_add_refusal_test(refuse_compression_recipe_blocks_small compression
  "compression: --recipe-blocks 7 must be 0 \\(the material's\\) or >= 8 \\(calibrate's and rc_beam's smallest" --threads 1 --material beam --recipe-blocks 7)
tessera_add_refusal_test(refuse_compression_one_block compression
  "compression: --blocks 1 must be 0 \\(the material's block size\\) or >= 2" --threads 1 --blocks 1)
tessera_add_refusal_test(refuse_direct_tension_recipe_blocks_small direct_tension
  "direct_tension: --recipe-blocks 2 must be 0 \\(the material's\\) or >= 8 \\(calibrate's and rc_beam's smallest" --threads 1 --material beam --recipe-blocks 2)
tessera_add_refusal_test(refuse_brazilian_params_g_c_slip brazilian
  "entries\\[0\\].G_c_J_per_m2: applies to law crushing only \\(this entry's law is slip_softening\\)"
  --threads 1 --material beam --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_slip_with_gc.json)
tessera_add_refusal_test(refuse_calibrate_targets_fit_gc calibrate
  "calibrate: --fit gc needs --law crushing \\(--law slip_softening has no G_c\\)" --threads 1 --targets tension
  --law slip_softening --fit gc)

# ---- --params on brazilian and compression (issue #63 item 4): calibrated.json carries the whole
# concrete (law, scales, c_0/f_T, phi_0, phi_res, G_II, cap; common/concrete_set.hpp). The beam file
# tests/data/concrete_beam_slip.json holds the slip-softening set that met f_c (phi_0 58, phi_res 15,
# G_II 300 J/m^2, cap 100 MPa) for the 250-block beam recipe at 30 mm zoning. Loaded, each driver runs
# exactly the set its flags give (measured, same curve.csv bits): the quick disc to 1 mm f_sp / f_T
# 3.831 (flags: --material beam --law slip_softening --phi-deg 58 --phi-res-deg 15 --g-ii 300 --cap 100e6),
# the 100 x 100 x 200 mm prism f_c 37.75 MPa at 1.56e-3 (the same flags).
tessera_add_example_test(brazilian NAME example_brazilian_params_quick
  ARGS --quick --threads 1 --material beam --max-displacement 1e-3
       --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_slip.json
  CHECKS "law STREQUAL slip_softening" "g_ii_J_per_m2 EQUAL 300" "cap_Pa EQUAL 100000000" "phi_0_deg EQUAL 58"
         "split STREQUAL ON" "f_sp_over_f_T GREATER 3.826" "f_sp_over_f_T LESS 3.836"
  TIMEOUT 300)
tessera_add_example_test(compression NAME example_compression_params_quick
  ARGS --quick --threads 1 --no-vtk --shape prism --diameter 0.1 --height 0.2 --max-strain 5e-3
       --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_slip.json
  CHECKS "law STREQUAL slip_softening" "G_II_J_per_m2 EQUAL 300" "cap_Pa EQUAL 100000000" "phi_res_deg EQUAL 15"
         "peak STREQUAL ON" "f_c_Pa GREATER 37.70e6" "f_c_Pa LESS 37.80e6"
  TIMEOUT 600)
# Refusals: a file of another recipe (material, block count, zoning) names both values; a concrete flag
# beside --params; a law the recipe does not have; a driver that applies the scales only
# (direct_tension, rc_tie) refuses a file whose set is not the study's, naming the field.
set(concrete_params_dir ${PROJECT_SOURCE_DIR}/tests/data)
tessera_add_refusal_test(refuse_brazilian_params_material brazilian
  "was fitted on the prism recipe, this run needs the beam recipe"
  --threads 1 --material beam --params ${concrete_params_dir}/concrete_prism_phi40.json)
tessera_add_refusal_test(refuse_brazilian_params_blocks brazilian
  "concrete_beam_slip.json has no entry for 500 blocks \\(it has 250\\)"
  --threads 1 --material beam --recipe-blocks 500 --params ${concrete_params_dir}/concrete_beam_slip.json)
tessera_add_refusal_test(refuse_brazilian_params_zoning brazilian
  "was fitted with a face zoning edge of 0.03 m, this run uses 0.05 m"
  --threads 1 --material beam --zone-edge 0.05 --params ${concrete_params_dir}/concrete_beam_slip.json)
tessera_add_refusal_test(refuse_brazilian_params_flag brazilian
  "brazilian: --phi-deg with --params .*: the file sets the concrete"
  --threads 1 --material beam --phi-deg 40 --params ${concrete_params_dir}/concrete_beam_slip.json)
tessera_add_refusal_test(refuse_brazilian_params_law brazilian
  "entries\\[0\\].law = 'slip_softening' is built for the beam recipe, this file's is 'prism'"
  --threads 1 --params ${concrete_params_dir}/concrete_prism_slip.json)
tessera_add_refusal_test(refuse_compression_params_zoning compression
  "calibrated_beam_quick.json was fitted with a face zoning edge of 0.05 m, this run uses 0.03 m"
  --threads 1 --params ${concrete_params_dir}/calibrated_beam_quick.json)
tessera_add_refusal_test(refuse_compression_params_blocks compression
  "calibrated_beam_quick.json has no entry for 250 blocks \\(it has 60\\)"
  --threads 1 --zone-edge 0.05 --params ${concrete_params_dir}/calibrated_beam_quick.json)
tessera_add_refusal_test(refuse_compression_params_flag compression
  "compression: --cap with --params .*: the file sets the concrete"
  --threads 1 --cap 50e6 --params ${concrete_params_dir}/concrete_beam_slip.json)
tessera_add_refusal_test(refuse_direct_tension_params_full_set direct_tension
  "entry for 100 blocks has phi_0_deg = 40 \\(the study's: 35\\), which direct_tension does not apply"
  --threads 1 --quick --params ${concrete_params_dir}/concrete_prism_phi40.json)

# ---- calibrate --targets (issue #63 item 4): one concrete fitted to tension, splitting and compression at
# once, residuals on a held-out seed. --quick: the beam recipe of calibrate --quick (60 blocks, 50 mm
# zoning; tension on its 37-block prism), a 12-block disc, a 23-block 100 x 100 x 200 mm prism, seed 1
# fitted, seed 2 held out, one compass iteration on the strength scale (at most 3 evaluations and the
# held-out one). Then brazilian loads the calibrated.json it wrote and, on the held-out seed with the
# same disc, must give the splitting figure calibrate reported for that seed (the same number: both run
# brazilian/disc.hpp with the file's concrete).
tessera_add_example_test(calibrate NAME example_calibrate_targets_quick
  ARGS --targets tension,splitting,compression --quick --seed 1 --threads 1
  FILES calibrated.json residuals.csv targets.csv
  CHECKS "mode STREQUAL targets" "material STREQUAL beam" "blocks EQUAL 60" "residual_count EQUAL 4"
         "evaluations LESS 4" "holdout_tension_reached EQUAL 1" "holdout_splitting_reached EQUAL 1"
         "holdout_tension_value GREATER 2.0e6" "holdout_tension_value LESS 3.0e6"
  TIMEOUT 600)
tessera_add_example_test(brazilian NAME example_brazilian_params_from_targets
  ARGS --quick --threads 1 --seed 2 --material beam --recipe-blocks 60 --zone-edge 0.05 --blocks 12
       --params ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_calibrate_targets_quick/calibrated.json
  CHECKS "split STREQUAL ON" "recipe_blocks EQUAL 60"
  TIMEOUT 300)
set_tests_properties(example_brazilian_params_from_targets PROPERTIES DEPENDS example_calibrate_targets_quick)
# tessera_add_targets_rerun_test(NAME CALIBRATE BRAZILIAN FIELD...): NAME passes when the brazilian
# example test BRAZILIAN (run on calibrate's held-out seed with its calibrated.json) gives the
# splitting figure the calibrate example test CALIBRATE reported for that seed, and its summary.json
# has each FIELD as the file's entry has it.
function(tessera_add_targets_rerun_test name calibrate brazilian)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/example_out)
  add_test(NAME ${name}
           COMMAND ${CMAKE_COMMAND} -E env python3 -c
                   "import json,sys; c=json.load(open(sys.argv[1])); b=json.load(open(sys.argv[2])); e=json.load(open(sys.argv[3]))['entries'][0]; ok=abs(c['holdout_splitting_value']-b['f_sp_over_f_T'])<=1e-12*b['f_sp_over_f_T'] and all(b[k]==e[k] for k in sys.argv[4:]); print(c['holdout_splitting_value'], b['f_sp_over_f_T'], [e[k] for k in sys.argv[4:]]); sys.exit(0 if ok else 1)"
                   ${out}/${calibrate}/summary.json ${out}/${brazilian}/summary.json ${out}/${calibrate}/calibrated.json
                   ${ARGN})
  set_tests_properties(${name} PROPERTIES DEPENDS ${brazilian})
endfunction()
tessera_add_targets_rerun_test(example_calibrate_targets_rerun_matches example_calibrate_targets_quick
                               example_brazilian_params_from_targets strength_scale cohesion_ratio)
# The same file loaded by direct_tension --material beam (direct_tension/concrete.hpp) on the held-out
# seed: the tension prism of calibrate's tension target, so its peak must be the tension value calibrate
# reported for that seed, to the bit (both run direct_tension/tension_test.hpp on make_beam_prism's scene
# with the file's concrete at 5 nm a step; only the stop past the peak differs).
tessera_add_example_test(direct_tension NAME example_direct_tension_params_from_targets
  ARGS --quick --threads 1 --seed 2 --material beam --recipe-blocks 60 --zone-edge 0.05
       --params ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_calibrate_targets_quick/calibrated.json
  CHECKS "material STREQUAL beam" "recipe_blocks EQUAL 60" "law STREQUAL study"
  TIMEOUT 300)
set_tests_properties(example_direct_tension_params_from_targets PROPERTIES DEPENDS example_calibrate_targets_quick)
if(TEST example_direct_tension_params_from_targets)
  add_test(NAME example_direct_tension_targets_rerun_matches
           COMMAND ${CMAKE_COMMAND} -E env python3 -c
                   "import json,sys; c=json.load(open(sys.argv[1]))['holdout_tension_value']; d=json.load(open(sys.argv[2]))['peak_stress_Pa']; print(c, d); sys.exit(0 if c == d else 1)"
                   ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_calibrate_targets_quick/summary.json
                   ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_direct_tension_params_from_targets/summary.json)
  set_tests_properties(example_direct_tension_targets_rerun_matches PROPERTIES
                       DEPENDS example_direct_tension_params_from_targets LABELS example)
endif()
# calibrate --targets --law crushing --fit gc: the quick disc on seed 1, one compass iteration on G_c
# from 20 kJ/m^2 (10 s): calibrated.json carries the law, G_c and the residual; brazilian loads it and
# on the held-out seed 2 gives the splitting figure calibrate reported for that seed.
tessera_add_example_test(calibrate NAME example_calibrate_targets_crushing_quick
  ARGS --targets splitting --law crushing --fit gc --quick --seed 1 --threads 1
  FILES calibrated.json
  CHECKS "mode STREQUAL targets" "law STREQUAL crushing" "G_c_J_per_m2 GREATER 1000" "cap_residual GREATER 0.099"
         "cap_residual LESS 0.101" "holdout_splitting_reached EQUAL 1"
  TIMEOUT 300)
tessera_add_example_test(brazilian NAME example_brazilian_params_from_crushing_targets
  ARGS --quick --threads 1 --seed 2 --material beam --recipe-blocks 60 --zone-edge 0.05 --blocks 12
       --params ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_calibrate_targets_crushing_quick/calibrated.json
  CHECKS "split STREQUAL ON" "law STREQUAL crushing" "G_c_J_per_m2 GREATER 1000"
  TIMEOUT 300)
set_tests_properties(example_brazilian_params_from_crushing_targets PROPERTIES
                     DEPENDS example_calibrate_targets_crushing_quick)
tessera_add_targets_rerun_test(example_calibrate_targets_crushing_rerun_matches example_calibrate_targets_crushing_quick
                               example_brazilian_params_from_crushing_targets G_c_J_per_m2 cap_residual)
# calibrate --targets --law mixed_mode --fit strength,gii: the quick disc on seed 1, one compass iteration
# on the strength scale and G_II from the law's default (c_0/f_T) G_f = 120 J/m^2 (15 s; measured: s
# 0.833 and G_II 100 J/m^2, splitting 1.821 on seed 1, 1.939 on the held-out seed 2). calibrated.json
# carries the law and the G_II the fit ran (written out, never the default); brazilian loads it and on
# seed 2 gives the splitting figure calibrate reported for that seed, with that G_II.
tessera_add_example_test(calibrate NAME example_calibrate_targets_mixed_mode_quick
  ARGS --targets splitting --law mixed_mode --fit strength,gii --quick --seed 1 --threads 1
  FILES calibrated.json
  CHECKS "mode STREQUAL targets" "law STREQUAL mixed_mode" "G_II_J_per_m2 GREATER 60" "G_II_J_per_m2 LESS 150"
         "holdout_splitting_reached EQUAL 1" "holdout_splitting_value GREATER 1.0" "holdout_splitting_value LESS 4.0"
  TIMEOUT 300)
tessera_add_example_test(brazilian NAME example_brazilian_params_from_mixed_mode_targets
  ARGS --quick --threads 1 --seed 2 --material beam --recipe-blocks 60 --zone-edge 0.05 --blocks 12
       --params ${CMAKE_CURRENT_BINARY_DIR}/example_out/example_calibrate_targets_mixed_mode_quick/calibrated.json
  CHECKS "split STREQUAL ON" "law STREQUAL mixed_mode" "g_ii_J_per_m2 GREATER 60" "g_ii_J_per_m2 LESS 150"
  TIMEOUT 300)
set_tests_properties(example_brazilian_params_from_mixed_mode_targets PROPERTIES
                     DEPENDS example_calibrate_targets_mixed_mode_quick)
tessera_add_targets_rerun_test(example_calibrate_targets_mixed_mode_rerun_matches example_calibrate_targets_mixed_mode_quick
                               example_brazilian_params_from_mixed_mode_targets strength_scale cohesion_ratio law)
# A move the law refuses is not run and is said: from G_II 65 J/m^2, the strength's step up (x 1.5) would
# need G_II above c_0^2/(2 k_s) = 135 J/m^2 for the quick beam's contacts, so calibrate prints the
# refusal and tries the step down (2 evaluations; summary.json refused_moves).
tessera_add_example_test(calibrate NAME example_calibrate_targets_refused_move
  ARGS --targets splitting --law mixed_mode --g-ii 65 --fit strength --step 0.5 --quick --seed 1 --threads 1
  CHECKS "refused_moves EQUAL 1" "evaluations EQUAL 2" "strength_scale LESS 1.01"
  TIMEOUT 300)
# rc_beam --params with a mixed-mode entry (tests/data/concrete_beam_mixed_quick.json: G_II 70 J/m^2,
# the study's other values, the quick beam's recipe) runs the beam its flags give, to the bit, and
# records the file's G_II. Refused, naming the value: an entry of law mixed_mode without G_II, with G_c
# (a crushing field), with a G_II below the law's bound for these contacts (60 J/m^2); G_II in an entry
# of the study's law; mixed_mode with the crushing flags or the prism recipe in calibrate.
tessera_add_example_test(rc_beam NAME example_rc_beam_mixed_mode_g_ii_quick
  ARGS --quick --threads 1 --no-vtk --law mixed_mode --g-ii 70 --max-deflection 4e-4
  FILES curve.csv
  CHECKS "law STREQUAL mixed_mode" "g_ii_J_per_m2 EQUAL 70" "energy_balance_error_rel LESS 1e-3"
  TIMEOUT 300)
tessera_add_example_test(rc_beam NAME example_rc_beam_params_mixed_mode_quick
  ARGS --quick --threads 1 --no-vtk --max-deflection 4e-4
       --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_quick.json
  FILES curve.csv
  CHECKS "parameters STREQUAL calibrated" "law STREQUAL mixed_mode" "g_ii_J_per_m2 EQUAL 70"
  TIMEOUT 300)
tessera_add_same_curve_test(example_rc_beam_params_mixed_mode_same_bits example_rc_beam_params_mixed_mode_quick
                            example_rc_beam_mixed_mode_g_ii_quick)
tessera_add_refusal_test(refuse_rc_beam_params_mixed_no_g_ii rc_beam
  "concrete_beam_mixed_no_gii.json: entries\\[0\\]: law mixed_mode needs \"G_II_J_per_m2\""
  --threads 1 --quick --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_no_gii.json)
tessera_add_refusal_test(refuse_brazilian_params_mixed_g_c brazilian
  "entries\\[0\\].G_c_J_per_m2: applies to law crushing only \\(this entry's law is mixed_mode\\)"
  --threads 1 --material beam --recipe-blocks 60 --zone-edge 0.05
  --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_with_gc.json)
tessera_add_refusal_test(refuse_rc_beam_params_mixed_small_g_ii rc_beam
  "G_II = 10 J/m.2 gives s_u .* G_II must exceed"
  --threads 1 --quick --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_mixed_small_gii.json)
tessera_add_refusal_test(refuse_compression_params_study_g_ii compression
  "entries\\[0\\].G_II_J_per_m2: applies to law slip_softening, crushing or mixed_mode only \\(this entry's law is study\\)"
  --threads 1 --zone-edge 0.05 --recipe-blocks 60 --params ${PROJECT_SOURCE_DIR}/tests/data/concrete_beam_study_with_gii.json)
tessera_add_refusal_test(refuse_calibrate_targets_mixed_g_c calibrate
  "calibrate: --g-c applies to --law crushing only \\(--law mixed_mode has no G_c in calibrated.json\\)" --threads 1 --targets splitting
  --law mixed_mode --g-c 1e4)
tessera_add_refusal_test(refuse_calibrate_targets_mixed_prism calibrate
  "calibrate: --law mixed_mode applies to --material beam only" --threads 1 --targets splitting --law mixed_mode
  --material prism)
tessera_add_refusal_test(refuse_calibrate_targets_name calibrate
  "calibrate: --targets: 'torsion' is not a target \\(tension, energy, splitting, compression, shear\\)" --threads 1
  --targets tension,torsion)
tessera_add_refusal_test(refuse_calibrate_targets_weights calibrate
  "calibrate: --weights '1,2,3' has 3 values for 2 targets" --threads 1 --targets tension,splitting --weights 1,2,3)
tessera_add_refusal_test(refuse_calibrate_targets_fit_gii calibrate
  "calibrate: --fit gii needs --law slip_softening" --threads 1 --targets tension --fit strength,gii)
# calibrate --targets shear (rc_beam/beam_shear_figure.hpp): rc_beam's 60-block beam with bars that cannot
# yield, 50 mm zoning, 10 mm/s, the mixed-mode law with G_II 70 J/m^2, seed 2 fitted (no iteration) and
# seed 3 held out, to 1.2 mm at most (about 30 s of CPU; 474 s wall on a host loaded 4 times over).
# Seed 2's load falls 25 % below its peak (25.24 kN) at a dip at 0.89 mm (docs/studies/one_concrete.md,
# "How long a drop holds"): failure reached, the figure is that peak. Seed 3 fails at 3.37 mm, so by
# 1.2 mm it has NOT reached its event: residual exactly unreached_residual (10), not met, never the load
# at the stop. rc_beam with the same flags on seed 2 (the guide's shear-figure command) gives the same
# peak to the bit (tests/check_shear_target.py).
tessera_add_example_test(calibrate NAME example_calibrate_targets_shear_quick
  ARGS --targets shear --law mixed_mode --g-ii 70 --seed 2 --seeds 1 --holdout 1 --iterations 0
       --shear-max-deflection 0.0012 --threads 1
  FILES calibrated.json residuals.csv targets.csv
  CHECKS "mode STREQUAL targets" "law STREQUAL mixed_mode" "G_II_J_per_m2 EQUAL 70" "shear_blocks EQUAL 60"
         "evaluations EQUAL 1" "fit_shear_reached EQUAL 1" "holdout_shear_reached EQUAL 0"
         "holdout_shear_residual EQUAL 10" "holdout_shear_met STREQUAL OFF" "holdout_shear_value IS NULL"
  TIMEOUT 900)
tessera_add_example_test(rc_beam NAME example_rc_beam_shear_figure_seed2
  ARGS --steel-yield 1e12 --zone-edge 0.05 --rate 0.01 --max-deflection 0.0012 --threads 1 --no-vtk --blocks 60
       --law mixed_mode --g-ii 70 --seed 2
  FILES curve.csv
  CHECKS "failure_reached STREQUAL ON" "g_ii_J_per_m2 EQUAL 70"
  TIMEOUT 300)
set(shear_out ${CMAKE_CURRENT_BINARY_DIR}/example_out)
add_test(NAME example_calibrate_targets_shear_matches_rc_beam
         COMMAND ${CMAKE_COMMAND} -E env python3 ${CMAKE_CURRENT_LIST_DIR}/check_shear_target.py
                 ${shear_out}/example_calibrate_targets_shear_quick ${shear_out}/example_rc_beam_shear_figure_seed2)
set_tests_properties(example_calibrate_targets_shear_matches_rc_beam PROPERTIES TIMEOUT 60
                     DEPENDS "example_calibrate_targets_shear_quick;example_rc_beam_shear_figure_seed2" LABELS example)
tessera_add_refusal_test(refuse_calibrate_targets_shear_prism calibrate
  "calibrate: --targets shear needs --material beam \\(rc_beam runs the beam's concrete.*--material prism"
  --threads 1 --targets tension,shear --material prism)
tessera_add_refusal_test(refuse_calibrate_targets_shear_blocks calibrate
  "^calibrate: --shear-blocks: value '5' must be >= 8\n$" --threads 1 --targets shear --shear-blocks 5)
tessera_add_refusal_test(refuse_calibrate_targets_shear_max_deflection calibrate
  "^calibrate: --shear-max-deflection: value '0.2' must be <= 0.05\n$" --threads 1 --targets shear
  --shear-max-deflection 0.2)
