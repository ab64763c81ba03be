#pragma once
// Analysis of runs: load-displacement curves (load drops, linear-branch slope, plateaus, curve
// errors), through-cracks along any axis, energy summaries, the sharpness of the stable step
// (spectral_bound.hpp). Reads solver and contact-set data; nothing in the step loop depends on it.
#include "analysis/cracks.hpp"
#include "analysis/curves.hpp"
#include "analysis/energy.hpp"
#include "analysis/spectral_bound.hpp"
