// Errors raised by the host side of mpvg (scene building, lowering, I/O).
// Per-element device code never throws; it reports through flags instead.
#pragma once
#include <stdexcept>
#include <string>

namespace mpvg {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace mpvg
