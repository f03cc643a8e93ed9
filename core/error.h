// Errors raised by the host side of mpvg (scene building, lowering, I/O).
// Per-element device code never throws; it reports through flags instead.
#pragma once
#include <new>
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
// Kinds of failure a caller may treat apart (Python: mpvg.ParseError, ...):
// the document is malformed (XML, PDF syntax, an invalid root or page);
// the work is valid but beyond this build or backend (no PDF support,
// device output without CUDA); the input or the machine's resources fall
// short (an unreadable file, --max-input, --max-memory, no CUDA device).
class ParseError : public Error {
 public:
  using Error::Error;
};
class UnsupportedError : public Error {
 public:
  using Error::Error;
};
class ResourceError : public Error {
 public:
  using Error::Error;
};
// Finer kinds: settings out of range or that cannot go together; a PDF
// encrypted without its password or with a wrong one; a render past its
// memory budget (--max-memory; the machine running out is still
// std::bad_alloc). Catching the kind above still catches these.
class OptionError : public Error {
 public:
  using Error::Error;
};
class PasswordError : public ParseError {
 public:
  using ParseError::ParseError;
};
class MemoryLimitError : public ResourceError {
 public:
  using ResourceError::ResourceError;
};
#endif

// The one line an exception is reported with: its message, or for an
// allocation that failed (std::bad_alloc, std::length_error from a
// container asked for too much) what happened rather than the type's name.
inline std::string error_message(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) || dynamic_cast<const std::length_error*>(&e))
    return "out of memory: the document needs more than this machine could give (see --max-memory)";
  return e.what();
}

}  // namespace mpvg
