// fuzz_path_data: the SVG path-data parser (parse_path_data in
// parsers/svg/svg_geometry.h), with arc continuations recorded as the
// marker code asks for them, the path's bounds under a transform, each
// segment as a cubic; and the same bytes as a points list (polyline,
// polygon) and as a transform list.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "parsers/svg/svg_geometry.h"
#include "parsers/svg/svg_values.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mpvg;
  using namespace mpvg::svg::detail;
  const std::string_view d(reinterpret_cast<const char*>(data), size);
  Path path;
  std::vector<uint32_t> arcs;
  (void)parse_path_data(d, path, &arcs);
  Bounds b;
  add_path_bounds(path, Affine::scale(2, 3), b);
  for (const Path::Segment& sg : path.segments())
    if (sg.type != SegmentType::Line) (void)segment_cubic(path, sg);
  const std::vector<Vec2> pts = parse_points(d);
  if (pts.size() >= 2) (void)poly_path(pts, true);
  (void)parse_transform(d);
  return 0;
}
