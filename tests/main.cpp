// The one Catch2 main of the test executable (tests/CMakeLists.txt globs every test source into it).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
