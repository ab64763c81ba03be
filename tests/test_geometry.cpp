// Tests for the geometry area (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>
