// Tests for the reinforcement area (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>
