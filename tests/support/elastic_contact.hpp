#pragma once
// A contact that stays elastic in the tests: the study's law with strengths far above any stress
// a test produces, and the given stiffnesses.

#include "tessera/presets.hpp"

namespace tessera::test {

/// study_tie_law params with stiffnesses k_n, k_s (Pa/m) and strengths of order 1e12 Pa.
[[nodiscard]] inline law::study_tie_law::params elastic_contact(real k_n, real k_s) {
  auto p = law::study_prism_params(100);
  p.k_n = k_n;
  p.k_s = k_s;
  p.tension.f_T = 1e12;
  p.tension.G_f = 1e13;  // zeta = 2 G_f / f_T must exceed eta = f_T / k_n
  p.shear.c_0 = 2e12;
  p.shear.c_res = 2e10;
  return p;
}

}  // namespace tessera::test
