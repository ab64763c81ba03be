// Tests for the laws area (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>
