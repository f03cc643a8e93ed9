// The text a scene-dump test compares (tests/test_svg_dumps.cpp, and the
// svg_dump tool that writes a new case's expected file): the scene dump
// (mpvg::dump) of an SVG file parsed as svg2png parses it, with no system
// fonts, followed by its warnings, one "warning: ..." line each.
#pragma once
#include <string>

#include "core/scene.h"
#include "parsers/svg/svg_parser.h"
#include "frame/scene_info.h"

namespace svg_test {

inline std::string dump_text(const std::string& path) {
  mpvg::svg::ParseOptions o;
  o.system_fonts = false;
  const mpvg::svg::ParseResult r = mpvg::svg::parse_svg_file(path, o);
  std::string out = mpvg::dump(r.scene);
  for (const std::string& w : r.warnings) out += "warning: " + w + "\n";
  return out;
}

}  // namespace svg_test
