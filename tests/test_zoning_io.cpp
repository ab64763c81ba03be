// Tests for the zoning_io area (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>
