// Output files that appear whole or not at all. Every file the converters
// write (PNGs of svg2png, its batches, pdf2png and the persistent
// renderer's clients) goes through write_output(): the bytes are written to
// a temporary file in the target's folder (".NAME.XXXXXX.part", created
// with the caller's umask), then renamed over the final name, so that a
// full disk, an error or a kill never leaves a truncated file under the
// final name. A failure removes the temporary file; so do SIGINT, SIGTERM,
// SIGHUP and SIGQUIT arriving while it exists (a SIGKILL can leave a
// ".part" file behind, never a truncated final file).
//
// An existing regular file keeps its permission bits, as when rewritten in
// place. A target that exists and is no regular file (a pipe, /dev/stdout,
// a terminal) is written directly: it cannot be replaced; so is a writable
// file in a folder the caller may not create files in. "-" is standard
// output.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mpvg {

// Throws mpvg::Error "cannot write 'PATH': REASON" (strerror of the
// failing call: "No space left on device", "Permission denied", "Is a
// directory").
void write_output(const std::string& path, const uint8_t* data, size_t size);
inline void write_output(const std::string& path, const std::vector<uint8_t>& bytes) {
  write_output(path, bytes.data(), bytes.size());
}

}  // namespace mpvg
