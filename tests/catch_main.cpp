// Catch2 v2 needs one translation unit that provides main; v3's
// Catch2::Catch2WithMain brings its own.
#if __has_include(<catch2/catch_all.hpp>) && !defined(MPVG_CATCH2_V2)
namespace mpvg_tests { int catch3_has_its_own_main = 0; }
#else
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
int main(int argc, char* argv[]) { return Catch::Session().run(argc, argv); }
#endif
