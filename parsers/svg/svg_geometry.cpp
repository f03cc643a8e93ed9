#include "parsers/svg/svg_geometry.h"

#include <algorithm>
#include <cmath>

#include "stroker/stroke_curve.h"
#include "parsers/svg/svg_values.h"

namespace mpvg::svg::detail {

// ---------------------------------------------------------------- PathBuilder

void PathBuilder::begin_segment() {
  if (pending_move_ || !path_.has_current_point()) {
    path_.move_to(current_);
    pending_move_ = false;
  }
  after_move_ = false;
}

void PathBuilder::move_to(Vec2 p) {
  current_ = start_ = p;
  pending_move_ = true;
  after_move_ = true;
}

void PathBuilder::line_to(Vec2 p) {
  begin_segment();
  path_.line_to(p);
  current_ = p;
}

void PathBuilder::quad_to(Vec2 p1, Vec2 p2) {
  begin_segment();
  path_.quad_to(p1, p2);
  current_ = p2;
}

void PathBuilder::rquad_to(Vec2 p1, Vec2 p2, double w) {
  begin_segment();
  path_.rquad_to(p1, p2, w);
  current_ = p2;
}

void PathBuilder::cubic_to(Vec2 p1, Vec2 p2, Vec2 p3) {
  begin_segment();
  path_.cubic_to(p1, p2, p3);
  current_ = p3;
}

void PathBuilder::close() {
  if (pending_move_) {
    // "M x y Z" is a zero-length subpath: a closed contour without
    // segments, which fills nothing but gets round or square caps when
    // stroked (SVG 2 painting.html#LineCaps). A second Z adds nothing.
    if (after_move_) {
      path_.move_to(current_);
      path_.close();
      after_move_ = false;
    }
    return;
  }
  path_.close();
  // After a closepath the current point is the subpath's start, and a
  // following drawing command starts a new subpath there (SVG 2 paths.html#PathDataClosePathCommand).
  current_ = start_;
  pending_move_ = true;
}

void PathBuilder::arc_to(double rx, double ry, double x_axis_rotation_deg, bool large_arc, bool sweep,
                         Vec2 p) {
  const Vec2 p0 = current_;
  // F.6.2: identical endpoints omit the arc; a zero radius makes it a line.
  if (p0 == p) return;
  rx = std::fabs(rx);
  ry = std::fabs(ry);
  if (rx == 0 || ry == 0) {
    line_to(p);
    return;
  }
  double sn_phi, cs_phi;
  sincos_snapped(std::fmod(x_axis_rotation_deg, 360.0) * (M_PI / 180.0), sn_phi, cs_phi);

  // F.6.5.1: the midpoint difference in the ellipse's axis frame.
  const double dx2 = (p0.x - p.x) / 2, dy2 = (p0.y - p.y) / 2;
  const double x1p = cs_phi * dx2 + sn_phi * dy2;
  const double y1p = -sn_phi * dx2 + cs_phi * dy2;

  // F.6.6.2-3: radii too small to span the endpoints are scaled up.
  const double lambda = (x1p * x1p) / (rx * rx) + (y1p * y1p) / (ry * ry);
  if (lambda > 1) {
    const double k = std::sqrt(lambda);
    rx *= k;
    ry *= k;
  }

  // F.6.5.2: the center in the axis frame; the sign picks one of the two
  // candidate ellipses from the flags.
  const double rx2 = rx * rx, ry2 = ry * ry;
  const double num = rx2 * ry2 - rx2 * y1p * y1p - ry2 * x1p * x1p;
  const double den = rx2 * y1p * y1p + ry2 * x1p * x1p;
  double coef = (num > 0 && den > 0) ? std::sqrt(num / den) : 0;
  if (large_arc == sweep) coef = -coef;
  const double cxp = coef * rx * y1p / ry;
  const double cyp = -coef * ry * x1p / rx;

  // F.6.5.3: back to user space.
  const Vec2 c{cs_phi * cxp - sn_phi * cyp + (p0.x + p.x) / 2,
               sn_phi * cxp + cs_phi * cyp + (p0.y + p.y) / 2};

  // F.6.5.5-6: start angle and sweep, on the unit circle of the ellipse.
  const Vec2 u{(x1p - cxp) / rx, (y1p - cyp) / ry};
  const Vec2 v{(-x1p - cxp) / rx, (-y1p - cyp) / ry};
  const double theta1 = std::atan2(u.y, u.x);
  double dtheta = std::atan2(cross(u, v), dot(u, v));
  if (!sweep && dtheta > 0) dtheta -= 2 * M_PI;
  if (sweep && dtheta < 0) dtheta += 2 * M_PI;

  // Radii or coordinates so extreme that the arithmetic above overflows
  // (a radius under ~1e-154 squares to 0, scaling the radii up to inf): the
  // arc is degenerate, drawn as the line F.6.2 draws for a zero radius.
  if (!(std::isfinite(dtheta) && std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(rx) && std::isfinite(ry))) {
    line_to(p);
    return;
  }

  // Pieces of at most 90°. On the unit circle a piece from a0 to a1 is the
  // conic with its middle control point at the tangents' intersection,
  // (cos a0 + cos a1, sin a0 + sin a1) / (1 + cos(a1 - a0)), and middle weight
  // cos((a1 - a0) / 2). The ellipse is an affine image of the circle and
  // conics are affinely invariant: map the control points, keep the weight.
  const int n = std::max(1, static_cast<int>(std::ceil(std::fabs(dtheta) / (M_PI / 2) - 1e-9)));
  const double delta = dtheta / n;
  const double w = std::cos(delta / 2);
  const double inv = 1 / (1 + std::cos(delta));
  auto to_user = [&](double ux, double uy) {
    const double ex = rx * ux, ey = ry * uy;
    return Vec2{cs_phi * ex - sn_phi * ey + c.x, sn_phi * ex + cs_phi * ey + c.y};
  };
  double s0, c0;
  sincos_snapped(theta1, s0, c0);
  for (int i = 0; i < n; i++) {
    double s1, c1;
    sincos_snapped(theta1 + (i + 1) * delta, s1, c1);
    const Vec2 ctrl = to_user((c0 + c1) * inv, (s0 + s1) * inv);
    // The last piece ends exactly on the requested endpoint.
    const Vec2 end = i == n - 1 ? p : to_user(c1, s1);
    if (i > 0) arc_continuations_.push_back(static_cast<uint32_t>(path_.segments().size()));
    rquad_to(ctrl, end, w);
    s0 = s1;
    c0 = c1;
  }
}

// ---------------------------------------------------------------- path data

namespace {

// A switch, not strchr over the letters: asked before every command and
// every implicit repetition.
bool is_command(char c) {
  switch (c) {
    case 'M': case 'm': case 'L': case 'l': case 'H': case 'h': case 'V': case 'v': case 'C': case 'c':
    case 'S': case 's': case 'Q': case 'q': case 'T': case 't': case 'A': case 'a': case 'Z': case 'z':
      return true;
    default:
      return false;
  }
}

bool starts_number(char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+'; }

}  // namespace

bool parse_path_data(std::string_view d, Path& out, std::vector<uint32_t>* arc_continuations) {
  Scanner s(d);
  PathBuilder pb;
  // Smooth curves reflect the previous control point only when the previous
  // command was of the same family (SVG 2 paths.html#PathDataCubicBezierCommands,
  // #PathDataQuadraticBezierCommands).
  enum class Prev { Other, Cubic, Quad } prev = Prev::Other;
  Vec2 ctrl;
  char cmd = 0;
  bool started = false;
  bool ok = true;

  auto num = [&](double& v) {
    s.skip_ws();
    const auto n = s.number();
    if (!n) return false;
    v = *n;
    s.skip_comma_ws();
    return true;
  };
  auto flag = [&](bool& f) {
    s.skip_ws();
    const auto b = s.flag();
    if (!b) return false;
    f = *b;
    s.skip_comma_ws();
    return true;
  };

  s.skip_ws();
  while (!s.at_end()) {
    const char c = s.peek();
    if (is_command(c)) {
      cmd = c;
      s.consume(c);
    } else if (!(cmd && cmd != 'Z' && cmd != 'z' && starts_number(c))) {
      ok = false;  // neither a command nor an implicit repetition
      break;
    }
    // Path data must begin with a moveto (SVG 2 paths.html#PathDataBNF).
    if (!started && cmd != 'M' && cmd != 'm') {
      ok = false;
      break;
    }
    started = true;
    const bool rel = cmd >= 'a' && cmd <= 'z';
    const Vec2 cur = pb.current_point();
    const Vec2 base = rel ? cur : Vec2{};
    Prev next = Prev::Other;
    bool good = true;
    switch (cmd) {
      case 'M':
      case 'm': {
        double x, y;
        if ((good = num(x) && num(y))) {
          pb.move_to(base + Vec2{x, y});
          // Further coordinate pairs are implicit linetos.
          cmd = rel ? 'l' : 'L';
        }
        break;
      }
      case 'L':
      case 'l': {
        double x, y;
        if ((good = num(x) && num(y))) pb.line_to(base + Vec2{x, y});
        break;
      }
      case 'H':
      case 'h': {
        double x;
        if ((good = num(x))) pb.line_to({rel ? cur.x + x : x, cur.y});
        break;
      }
      case 'V':
      case 'v': {
        double y;
        if ((good = num(y))) pb.line_to({cur.x, rel ? cur.y + y : y});
        break;
      }
      case 'C':
      case 'c': {
        double x1, y1, x2, y2, x, y;
        if ((good = num(x1) && num(y1) && num(x2) && num(y2) && num(x) && num(y))) {
          ctrl = base + Vec2{x2, y2};
          pb.cubic_to(base + Vec2{x1, y1}, ctrl, base + Vec2{x, y});
          next = Prev::Cubic;
        }
        break;
      }
      case 'S':
      case 's': {
        double x2, y2, x, y;
        if ((good = num(x2) && num(y2) && num(x) && num(y))) {
          const Vec2 c1 = prev == Prev::Cubic ? cur + (cur - ctrl) : cur;
          ctrl = base + Vec2{x2, y2};
          pb.cubic_to(c1, ctrl, base + Vec2{x, y});
          next = Prev::Cubic;
        }
        break;
      }
      case 'Q':
      case 'q': {
        double x1, y1, x, y;
        if ((good = num(x1) && num(y1) && num(x) && num(y))) {
          ctrl = base + Vec2{x1, y1};
          pb.quad_to(ctrl, base + Vec2{x, y});
          next = Prev::Quad;
        }
        break;
      }
      case 'T':
      case 't': {
        double x, y;
        if ((good = num(x) && num(y))) {
          ctrl = prev == Prev::Quad ? cur + (cur - ctrl) : cur;
          pb.quad_to(ctrl, base + Vec2{x, y});
          next = Prev::Quad;
        }
        break;
      }
      case 'A':
      case 'a': {
        double rx, ry, angle, x, y;
        bool large, sweep;
        if ((good = num(rx) && num(ry) && num(angle) && flag(large) && flag(sweep) && num(x) && num(y)))
          pb.arc_to(rx, ry, angle, large, sweep, base + Vec2{x, y});
        break;
      }
      default:  // 'Z', 'z'
        pb.close();
        s.skip_ws();
        break;
    }
    if (!good) {
      ok = false;
      break;
    }
    prev = next;
  }
  if (arc_continuations) *arc_continuations = pb.arc_continuations();
  out = pb.take();
  return ok;
}

// ---------------------------------------------------------------- shapes

std::vector<Vec2> parse_points(std::string_view text) {
  Scanner s(text);
  std::vector<Vec2> pts;
  s.skip_ws();
  double pending = 0;
  bool have_x = false;
  while (!s.at_end()) {
    const auto v = s.number();
    if (!v) break;
    if (have_x)
      pts.push_back({pending, *v});
    else
      pending = *v;
    have_x = !have_x;
    s.skip_comma_ws();
  }
  return pts;
}

Path rect_path(double x, double y, double w, double h, double rx, double ry) {
  PathBuilder pb;
  if (rx <= 0 || ry <= 0) {
    pb.move_to({x, y});
    pb.line_to({x + w, y});
    pb.line_to({x + w, y + h});
    pb.line_to({x, y + h});
    pb.close();
    return pb.take();
  }
  // SVG 2 shapes.html#RectElement: start at (x + rx, y), go clockwise; each corner is a quarter
  // ellipse, i.e. a conic with its control point on the corner and weight
  // cos(45°). Straight edges of zero length (rx = w / 2) are left out.
  const double k = M_SQRT1_2;
  auto edge = [&](Vec2 p) {
    if (pb.current_point() != p) pb.line_to(p);
  };
  pb.move_to({x + rx, y});
  edge({x + w - rx, y});
  pb.rquad_to({x + w, y}, {x + w, y + ry}, k);
  edge({x + w, y + h - ry});
  pb.rquad_to({x + w, y + h}, {x + w - rx, y + h}, k);
  edge({x + rx, y + h});
  pb.rquad_to({x, y + h}, {x, y + h - ry}, k);
  edge({x, y + ry});
  pb.rquad_to({x, y}, {x + rx, y}, k);
  pb.close();
  return pb.take();
}

Path ellipse_path(double cx, double cy, double rx, double ry) {
  // SVG 2 shapes.html#CircleElement, #EllipseElement: four quarter arcs starting at (cx + rx, cy) in the
  // direction of positive angles.
  const double k = M_SQRT1_2;
  PathBuilder pb;
  pb.move_to({cx + rx, cy});
  pb.rquad_to({cx + rx, cy + ry}, {cx, cy + ry}, k);
  pb.rquad_to({cx - rx, cy + ry}, {cx - rx, cy}, k);
  pb.rquad_to({cx - rx, cy - ry}, {cx, cy - ry}, k);
  pb.rquad_to({cx + rx, cy - ry}, {cx + rx, cy}, k);
  pb.close();
  return pb.take();
}

Path line_path(Vec2 p0, Vec2 p1) {
  PathBuilder pb;
  pb.move_to(p0);
  pb.line_to(p1);
  return pb.take();
}

Path poly_path(const std::vector<Vec2>& points, bool close) {
  PathBuilder pb;
  if (points.size() < 2) return pb.take();
  pb.move_to(points[0]);
  for (size_t i = 1; i < points.size(); i++) pb.line_to(points[i]);
  if (close) pb.close();
  return pb.take();
}

// ---------------------------------------------------------------- bounds

void Bounds::add(Vec2 p) {
  x0 = std::min(x0, p.x);
  y0 = std::min(y0, p.y);
  x1 = std::max(x1, p.x);
  y1 = std::max(y1, p.y);
}

void Bounds::add(const Bounds& b) {
  if (b.empty()) return;
  add(Vec2{b.x0, b.y0});
  add(Vec2{b.x1, b.y1});
}

namespace {

// Real roots of a t^2 + b t + c = 0 that lie strictly inside (0, 1).
int roots_in_unit_interval(double a, double b, double c, double t[2]) {
  int n = 0;
  auto keep = [&](double r) {
    if (r > 0 && r < 1) t[n++] = r;
  };
  const double scale = std::fabs(a) + std::fabs(b) + std::fabs(c);
  if (scale == 0) return 0;
  if (std::fabs(a) <= 1e-12 * scale) {
    if (b != 0) keep(-c / b);
    return n;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return 0;
  // Numerically stable form (no cancellation between -b and sqrt(disc)).
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  keep(q / a);
  if (q != 0) keep(c / q);
  return n;
}

}  // namespace

std::array<Vec2, 4> segment_cubic(const Path& path, const Path::Segment& sg) {
  const Vec2* q = &path.points()[sg.first_point];
  auto towards = [](Vec2 a, Vec2 b, double k) { return Vec2{a.x + k * (b.x - a.x), a.y + k * (b.y - a.y)}; };
  switch (sg.type) {
    case SegmentType::Quad: return {q[0], towards(q[0], q[1], 2.0 / 3), towards(q[2], q[1], 2.0 / 3), q[2]};
    case SegmentType::RQuad: {
      const double half = std::acos(std::clamp(path.weights()[sg.first_weight], -1.0, 1.0));
      const double k = half > 1e-12 ? 4.0 / 3.0 * std::tan(half / 2) / std::tan(half) : 2.0 / 3.0;
      return {q[0], towards(q[0], q[1], k), towards(q[2], q[1], k), q[2]};
    }
    case SegmentType::Cubic:
    case SegmentType::RCubic: return {q[0], q[1], q[2], q[3]};
    case SegmentType::Line: break;
  }
  return {q[0], q[0], q[1], q[1]};
}

void add_path_bounds(const Path& path, const Affine& m, Bounds& b) {
  const auto& pts = path.points();
  for (const Path::Segment& seg : path.segments()) {
    const int deg = segment_degree(seg.type);
    Vec2 q[4];
    for (int i = 0; i <= deg; i++) q[i] = m.apply(pts[seg.first_point + i]);
    b.add(q[0]);
    b.add(q[deg]);
    double t[2];
    switch (seg.type) {
      case SegmentType::Line: break;
      case SegmentType::Quad:
      case SegmentType::RQuad: {
        // Extrema of the conic (q0 B0 + w q1 B1 + q2 B2) / (B0 + w B1 + B2)
        // with Bernstein B0 = (1-t)^2, B1 = 2t(1-t), B2 = t^2. Writing the
        // numerator N and denominator D in the power basis, N'D - ND' = 0 is
        // the quadratic (n2 d1 - n1 d2) t^2 + 2 (n2 d0 - n0 d2) t + (n1 d0 - n0 d1).
        const double w = seg.type == SegmentType::RQuad ? path.weights()[seg.first_weight] : 1.0;
        const double d0 = 1, d1 = 2 * w - 2, d2 = 2 - 2 * w;
        for (int axis = 0; axis < 2; axis++) {
          const double a0 = axis ? q[0].y : q[0].x, a1 = axis ? q[1].y : q[1].x, a2 = axis ? q[2].y : q[2].x;
          const double n0 = a0, n1 = 2 * w * a1 - 2 * a0, n2 = a0 - 2 * w * a1 + a2;
          const int k =
              roots_in_unit_interval(n2 * d1 - n1 * d2, 2 * (n2 * d0 - n0 * d2), n1 * d0 - n0 * d1, t);
          for (int i = 0; i < k; i++) {
            const double u = 1 - t[i];
            const double b0 = u * u, b1 = 2 * w * t[i] * u, b2 = t[i] * t[i];
            const double den = b0 + b1 + b2;
            b.add(Vec2{(q[0].x * b0 + q[1].x * b1 + q[2].x * b2) / den,
                       (q[0].y * b0 + q[1].y * b1 + q[2].y * b2) / den});
          }
        }
        break;
      }
      case SegmentType::Cubic: {
        // B'(t)/3 = (p1-p0)(1-t)^2 + 2(p2-p1)t(1-t) + (p3-p2)t^2.
        for (int axis = 0; axis < 2; axis++) {
          const double a0 = axis ? q[0].y : q[0].x, a1 = axis ? q[1].y : q[1].x;
          const double a2 = axis ? q[2].y : q[2].x, a3 = axis ? q[3].y : q[3].x;
          const int k =
              roots_in_unit_interval(-a0 + 3 * a1 - 3 * a2 + a3, 2 * (a0 - 2 * a1 + a2), a1 - a0, t);
          for (int i = 0; i < k; i++) {
            const double u = 1 - t[i];
            const double b0 = u * u * u, b1 = 3 * u * u * t[i], b2 = 3 * u * t[i] * t[i],
                         b3 = t[i] * t[i] * t[i];
            b.add(Vec2{q[0].x * b0 + q[1].x * b1 + q[2].x * b2 + q[3].x * b3,
                       q[0].y * b0 + q[1].y * b1 + q[2].y * b2 + q[3].y * b3});
          }
        }
        break;
      }
      case SegmentType::RCubic:
        // Never produced by this frontend; the control hull is a safe bound.
        b.add(q[1]);
        b.add(q[2]);
        break;
    }
  }
}

double path_length(const Path& path) {
  using namespace stroking;
  const auto& pts = path.points();
  double total = 0;
  for (const Path::Segment& sg : path.segments()) {
    const Vec2* q = &pts[sg.first_point];
    Curve c;
    switch (sg.type) {
      case SegmentType::Line: total += length(q[1] - q[0]); continue;
      case SegmentType::Quad: c = {CURVE_QUAD, {q[0], q[1], q[2]}}; break;
      case SegmentType::RQuad: c = {CURVE_RQUAD, {q[0], q[1], q[2]}, path.weights()[sg.first_weight]}; break;
      case SegmentType::Cubic: c = {CURVE_CUBIC, {q[0], q[1], q[2], q[3]}}; break;
      case SegmentType::RCubic: continue;  // SVG geometry makes none
    }
    total += ArcTable(c).total();
  }
  return total;
}

std::optional<double> parse_path_length(std::string_view s) {
  const auto n = parse_number(s);
  if (!n || *n < 0) return std::nullopt;
  return n;
}

}  // namespace mpvg::svg::detail
