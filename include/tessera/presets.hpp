#pragma once
// Module header for presets/: the reference study's data and named solvers (never included by a
// generic room).
#include "presets/pulatsu2020.hpp"
#include "presets/mixed_mode.hpp"
