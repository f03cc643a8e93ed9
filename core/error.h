// Errors raised by the host side of mpvg (scene building, lowering, I/O).
// Per-element device code never throws; it reports through flags instead.
#pragma once
#include <stdexcept>
#include <string>

namespace mpvg {

// The public header (include/mpvg/mpvg.h) declares the same class, for
// programs that see no internal header; whichever comes first defines it.
#ifndef MPVG_INTERNAL_ERROR_DEFINED
#define MPVG_INTERNAL_ERROR_DEFINED 1
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};
#endif

}  // namespace mpvg
