// Tests for the mechanics area (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>
