// Tests for the stability area (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>
