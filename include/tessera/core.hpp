#pragma once
// Module header: basic types, exceptions, deterministic parallel loops.
#include "core/version.hpp"
#include "core/types.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/nodes.hpp"
