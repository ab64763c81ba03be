#pragma once
// Module header for law/. Owners add their headers here as they land.
#include "core.hpp"
#include "law/concepts.hpp"
