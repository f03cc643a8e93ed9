// Catch2 v2 (Debian 12: a single header) and v3 (newer distributions: a
// library with its own main) behind one include.
#pragma once
#if __has_include(<catch2/catch_all.hpp>) && !defined(MPVG_CATCH2_V2)
#include <catch2/catch_all.hpp>
#define MPVG_CATCH3 1
#else
#include <catch2/catch.hpp>
#endif
