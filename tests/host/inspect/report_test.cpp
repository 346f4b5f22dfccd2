// Report pictures and the HTML report: the right size, not blank, a single bad point visible,
// and a report that carries its pictures and numbers.
#include "host/inspect/html_report.h"
#include "host/inspect/view3d.h"

#include <CppUTest/TestHarness.h>

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <vector>

#include "host/inspect/deviation_map.h"
#include "host/inspect/inspect.h"
#include "host/inspect/view_mesh.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

struct Decoded {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

Decoded decode(const std::string& bytes) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  CHECK(png_image_begin_read_from_memory(&image, bytes.data(), bytes.size()));
  image.format = PNG_FORMAT_RGB;
  Decoded d;
  d.width = static_cast<int>(image.width);
  d.height = static_cast<int>(image.height);
  d.rgb.resize(PNG_IMAGE_SIZE(image));
  CHECK(png_image_finish_read(&image, nullptr, d.rgb.data(), 0, nullptr));
  return d;
}

std::vector<MapPoint> grid(double (*value)(int, int)) {
  std::vector<MapPoint> p;
  for (int j = 0; j <= 30; ++j)
    for (int i = 0; i <= 40; ++i) p.push_back({1.0 * i, 1.0 * j, value(i, j)});
  return p;
}

}  // namespace

TEST_GROUP(Report){};

namespace {

bool same(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// The largest difference in any channel: how far apart two colours look at the least.
int channel_gap(Rgb a, Rgb b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

bool has_pixel(const Decoded& d, Rgb c) {
  for (size_t k = 0; k + 2 < d.rgb.size(); k += 3) {
    if (d.rgb[k] == c.r && d.rgb[k + 1] == c.g && d.rgb[k + 2] == c.b) return true;
  }
  return false;
}

}  // namespace

// A profile tolerance drawn as inspection reports draw it: green about the nominal, the ramp's ends
// at the limits (a value on a limit is inside), and beyond each limit a colour that no value
// inside ever takes, so an out-of-tolerance point cannot be read as one near a limit.
TEST(Report, TheToleranceScaleIsGreenInsideAndDistinctBeyondEachLimit) {
  const double lower = -0.02, upper = 0.03;
  const Rgb green = tolerance_colour(0, lower, upper);
  CHECK(green.g > 2 * green.r && green.g > 2 * green.b);
  CHECK(same(tolerance_colour(0.004, lower, upper), green));
  CHECK(same(tolerance_colour(-0.004, lower, upper), green));
  const Rgb at_upper = tolerance_colour(upper, lower, upper), at_lower = tolerance_colour(lower, lower, upper);
  CHECK(at_upper.r > 2 * at_upper.g && at_upper.r > 2 * at_upper.b);  // red
  CHECK(at_lower.b > 2 * at_lower.r && at_lower.b > at_lower.g);        // blue
  CHECK(same(tolerance_colour(upper + 1e-9, lower, upper), kAboveUpperLimit));
  CHECK(same(tolerance_colour(lower - 1e-9, lower, upper), kBelowLowerLimit));
  CHECK(same(tolerance_colour(5.0, lower, upper), kAboveUpperLimit));
  for (int k = 0; k <= 1000; ++k) {
    const double value = k == 1000 ? upper : lower + (upper - lower) * k / 1000.0;  // the sum may round past it
    const Rgb inside = tolerance_colour(value, lower, upper);
    CHECK(channel_gap(inside, kAboveUpperLimit) >= 60);
    CHECK(channel_gap(inside, kBelowLowerLimit) >= 60);
  }
  CHECK(channel_gap(kAboveUpperLimit, kBelowLowerLimit) >= 60);
  // Limits that do not straddle 0 (a part that must stand proud by 0.01 to 0.05 mm): green at
  // their middle.
  CHECK(same(tolerance_colour(0.03, 0.01, 0.05), tolerance_colour(0, -0.01, 0.01)));
  CHECK(same(tolerance_colour(0.0, 0.01, 0.05), kBelowLowerLimit));
}

// With limits, the map and its bar use the tolerance scale: the bar names both limits and the two
// out-of-tolerance blocks, and the one point beyond the upper limit shows in its colour.
TEST(Report, AMapWithToleranceLimitsShowsAPointBeyondThemInTheOutOfToleranceColour) {
  std::vector<MapPoint> points = grid([](int i, int j) { return 0.0004 * (i - 20) + 0.0002 * (j - 15); });
  points[600].value_mm = 0.05;
  MapPicture picture;
  picture.scale.lower_mm = -0.02;
  picture.scale.upper_mm = 0.02;
  const std::string svg = deviation_map_svg(points, picture, "deviation");
  STRCMP_CONTAINS("&gt; +0.0200 mm", svg.c_str());
  STRCMP_CONTAINS("&lt; -0.0200 mm", svg.c_str());
  char above[16];
  std::snprintf(above, sizeof above, "#%02x%02x%02x", kAboveUpperLimit.r, kAboveUpperLimit.g, kAboveUpperLimit.b);
  STRCMP_CONTAINS((std::string("fill=\"") + above).c_str(), svg.c_str());
  const Decoded d = decode(deviation_map_png(points, picture));
  CHECK(has_pixel(d, kAboveUpperLimit));
  CHECK(has_pixel(d, tolerance_colour(0, -0.02, 0.02)));
  // Without the outlier no cell is out of tolerance: the colour is left to the bar's block.
  points[600].value_mm = 0.0;
  const std::string inside = deviation_map_svg(points, picture, "deviation");
  CHECK(inside.find(std::string("fill=\"") + above) == std::string::npos);
}

TEST(Report, DeviationMapHasItsSizeAndIsNotBlank) {
  const Decoded d = decode(deviation_map_png(grid([](int i, int j) { return 0.001 * (i - 20) + 0.0005 * (j - 15); }), MapPicture{}));
  LONGS_EQUAL(900, d.width);
  LONGS_EQUAL(600, d.height);
  std::set<uint32_t> colours;
  for (size_t k = 0; k + 2 < d.rgb.size(); k += 3) colours.insert(uint32_t{d.rgb[k]} << 16 | d.rgb[k + 1] << 8 | d.rgb[k + 2]);
  CHECK(colours.size() > 50);
}

TEST(Report, OneBadPointAmongManyStaysVisible) {
  std::vector<MapPoint> p;
  for (int j = 0; j <= 400; ++j)
    for (int i = 0; i <= 400; ++i) p.push_back({0.1 * i, 0.1 * j, 0.0});
  p[200 * 401 + 200].value_mm = 0.05;  // one point among 160,801
  const Decoded d = decode(deviation_map_png(p, MapPicture{}));
  bool saturated_red = false;
  for (size_t k = 0; k + 2 < d.rgb.size(); k += 3) saturated_red |= d.rgb[k] == 200 && d.rgb[k + 1] == 30 && d.rgb[k + 2] == 30;
  CHECK(saturated_red);
}

TEST(Report, SvgAndHtmlCarryThePicturesAndTheNumbers) {
  const std::string svg = deviation_map_svg(grid([](int i, int) { return 0.001 * i; }), MapPicture{}, "a <title>");
  STRCMP_CONTAINS("<svg xmlns=", svg.c_str());
  STRCMP_CONTAINS("a &lt;title&gt;", svg.c_str());
  STRCMP_CONTAINS("+0.0400 mm", svg.c_str());
  Inspection inspection;
  inspection.stats.count = 3;
  inspection.stats.rms = 0.0123;
  inspection.bands.push_back({0.01, 2, 2.0 / 3});
  ReportInputs in;
  in.points_file = "part.scan";
  in.inspection = &inspection;
  in.pictures.push_back({"deviation", deviation_map_png(grid([](int, int) { return 0.0; }), MapPicture{})});
  const std::string html = html_report(in);
  STRCMP_CONTAINS("data:image/png;base64,iVBORw0KGgo", html.c_str());  // the PNG signature
  STRCMP_CONTAINS("0.0123", html.c_str());
  STRCMP_CONTAINS("66.7 %", html.c_str());
  STRCMP_EQUAL("Zm9vYmFy", base64("foobar").c_str());
  STRCMP_EQUAL("Zm9vYg==", base64("foob").c_str());
  CHECK(html.find("serial number") == std::string::npos);  // no empty rows for fields not given
  // A picture with an SVG is shown as SVG; the part's fields head the table, escaped.
  in.pictures[0].svg = deviation_map_svg(grid([](int, int) { return 0.0; }), MapPicture{}, "deviation");
  in.fields.part = "lid <4711>";
  in.fields.serial = "SN-42";
  const std::string with_fields = html_report(in);
  STRCMP_CONTAINS("data:image/svg+xml;base64,", with_fields.c_str());
  STRCMP_CONTAINS("<tr><th>part</th><td>lid &lt;4711&gt;</td></tr>", with_fields.c_str());
  STRCMP_CONTAINS("<tr><th>serial number</th><td>SN-42</td></tr>", with_fields.c_str());
}

// Points beyond the surface's edge (their distance is to the edge, millimetres) are grey, on no
// scale: the maps' colours stay stretched to the part's deviations, a hundredth of a millimetre
// here, and under a tolerance they do not show as out of it. The captions say what grey is.
TEST(Report, PointsBeyondTheEdgeAreGreyAndDoNotStretchTheColours) {
  const double n = std::sqrt(1 + 0.01);  // tilted_plane: z = 1 + 0.1 x over 0..40 x 0..30
  std::vector<Point3> points;
  for (int j = 1; j < 30; j += 4) {
    for (int i = 1; i < 40; i += 4) points.push_back({1.0 * i, 1.0 * j, 1 + 0.1 * i + ((i + j) % 3 - 1) * 0.01 * n});
  }
  points.push_back({52, 15, 6.2});
  points.push_back({-12, 10, 1});
  const Inspection r = inspect(points, dg::test::tilted_plane(), {});
  LONGS_EQUAL(2, r.beyond_edge);
  std::string svg;
  std::vector<ReportPicture> pictures = inspection_pictures(r, &svg);
  STRCMP_CONTAINS("+0.0100 mm", svg.c_str());
  STRCMP_CONTAINS("grey: points beyond the surface's edge", pictures[0].caption.c_str());
  STRCMP_CONTAINS("grey: points beyond the surface's edge", pictures[3].caption.c_str());
  const Rgb grey = kMutedColour;
  CHECK(has_pixel(decode(pictures[0].png), grey));
  CHECK(has_pixel(decode(pictures[3].png), grey));
  // Under a tolerance the grey stays; no point is drawn in an out-of-tolerance colour.
  const ToleranceLimits limits{-0.02, 0.02};
  pictures = inspection_pictures(r, nullptr, &limits);
  const Decoded toleranced = decode(pictures[0].png);
  CHECK(has_pixel(toleranced, grey));
  const Rgb above = kAboveUpperLimit, below = kBelowLowerLimit;
  // The colour bar shows both out-of-tolerance colours: count them in the plot only (left of it).
  size_t out_of_tolerance = 0;
  for (int y = 0; y < toleranced.height; ++y) {
    for (int x = 0; x < toleranced.width - 220; ++x) {
      const uint8_t* px = &toleranced.rgb[(static_cast<size_t>(y) * toleranced.width + x) * 3];
      const Rgb c{px[0], px[1], px[2]};
      out_of_tolerance += same(c, above) || same(c, below);
    }
  }
  LONGS_EQUAL(0, out_of_tolerance);
  // The 3D view: the two points grey, the others on the scale.
  const std::string view = view3d_html(r, deviation_scale(nullptr), nullptr);
  char grey_text[64];
  std::snprintf(grey_text, sizeof grey_text, "%.4f,%.4f,%.4f", grey.r / 255.0, grey.g / 255.0, grey.b / 255.0);
  STRCMP_CONTAINS(grey_text, view.c_str());
  // Without points beyond the edge no cell is grey.
  points.resize(points.size() - 2);
  CHECK_FALSE(has_pixel(decode(inspection_pictures(inspect(points, dg::test::tilted_plane(), {}), nullptr)[0].png), grey));
}

// The uncertainty map: nothing without an uncertainty; with one, U = 2u placed where the surface
// is, darkest where u is largest (here one corner of a flat 40 x 30 mm surface) and white where it
// is zero, and the report lists u and U.
TEST(Report, TheUncertaintyMapShowsExpandedUncertaintyWhereTheSurfaceIs) {
  FittedSurface f;
  f.surface.degree_u = f.surface.degree_v = 1;
  f.surface.count_u = f.surface.count_v = 2;
  f.surface.knots_u = f.surface.knots_v = {0, 0, 1, 1};
  f.surface.control = {{0, 0, 1}, {0, 30, 1}, {40, 0, 1}, {40, 30, 1}};
  CHECK(uncertainty_picture(f).png.empty());
  f.uncertainty.computed = true;
  f.uncertainty.sigma_mm = 0.002;
  f.uncertainty.sigma_from = "test";
  f.uncertainty.rows = f.uncertainty.cols = 3;
  f.uncertainty.u_mm = {0, 0, 0, 0, 0, 0, 0, 0, 0.004};  // largest at u = v = 1: (40, 30) mm
  f.uncertainty.max_mm = 0.004;
  f.uncertainty.mean_mm = 0.004 / 9;
  const ReportPicture picture = uncertainty_picture(f);
  const Decoded d = decode(picture.png);
  LONGS_EQUAL(900, d.width);
  // The plot spans x 74.. (room for the mm axis) and y 20.., 604 x 452 pixels of 4-pixel cells for
  // 40 x 30 mm; the table's (40, 30) is its top right corner, (0, 0) bottom left.
  auto pixel = [&](int x, int y) { return &d.rgb[(static_cast<size_t>(y) * d.width + x) * 3]; };
  const uint8_t* top_right = pixel(74 + 604 - 8, 20 + 4);
  const uint8_t* bottom_left = pixel(74 + 4, 20 + 452 - 8);
  CHECK(top_right[1] < 80);        // saturated red: little green
  CHECK(bottom_left[1] > 240);     // white
  STRCMP_CONTAINS("U = 2u", picture.caption.c_str());
  ReportInputs in;
  in.surface = &f;
  const std::string html = html_report(in);
  STRCMP_CONTAINS("expanded uncertainty U = 2u", html.c_str());
  STRCMP_CONTAINS("0.0080 mm", html.c_str());
}

// Trimmed faces: each table point takes its own face's grid. Two faces split a flat 40 x 30 mm
// patch at x = 20; the right face is uncertain only at its far corner, the left not at all, and a
// node off the right face (at its near edge) does not bleed into the map.
TEST(Report, TheUncertaintyMapOfTrimmedFacesTakesEachPointsOwnFace) {
  FittedSurface f;
  BSplineSurface s;
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.control = {{0, 0, 1}, {0, 30, 1}, {40, 0, 1}, {40, 30, 1}};
  TrimmedFace left, right;
  left.surface = right.surface = s;
  left.loops = {{{0, 0}, {20, 0}, {20, 30}, {0, 30}}};
  right.loops = {{{20, 0}, {40, 0}, {40, 30}, {20, 30}}};
  for (TrimmedFace* face : {&left, &right}) {
    face->uncertainty.computed = true;
    face->uncertainty.sigma_mm = 0.002;
    face->uncertainty.sigma_from = "test";
    face->uncertainty.rows = face->uncertainty.cols = 3;
  }
  left.uncertainty.u_mm = {0, 0, kOffFace, 0, 0, kOffFace, 0, 0, kOffFace};
  right.uncertainty.u_mm = {kOffFace, 0, 0, kOffFace, 0, 0, kOffFace, 0, 0.004};
  right.uncertainty.max_mm = 0.004;
  f.faces = {left, right};
  CHECK(!uncertainty_picture(f).png.empty());
  f.faces[0].uncertainty.computed = false;  // a face without its grid: no map rather than a blank hole
  CHECK(uncertainty_picture(f).png.empty());
  f.faces[0].uncertainty.computed = true;
  const ReportPicture picture = uncertainty_picture(f);
  const Decoded d = decode(picture.png);
  auto pixel = [&](int x, int y) { return &d.rgb[(static_cast<size_t>(y) * d.width + x) * 3]; };
  CHECK(pixel(74 + 604 - 8, 20 + 4)[1] < 80);   // (40, 30): saturated
  CHECK(pixel(74 + 4, 20 + 4)[1] > 240);        // (0, 30): white, on the left face
  CHECK(pixel(74 + 4, 20 + 452 - 8)[1] > 240);  // (0, 0)
  STRCMP_CONTAINS("faces", picture.caption.c_str());
  ReportInputs in;
  in.surface = &f;
  STRCMP_CONTAINS("face 2: expanded uncertainty U = 2u", html_report(in).c_str());
}

TEST(Report, TheThreeDViewCarriesAtMostItsPointsWithTheirColours) {
  Inspection inspection;
  for (int i = 0; i < 50000; ++i) inspection.points.push_back({{0.01 * i, 0, 1}, {0.01 * i, 0, 1}, i == 0 ? 0.02 : 0.0});
  ColourScale scale;
  scale.range_mm = 0.02;
  const std::string html = view3d_html(inspection, scale, nullptr, 20000);
  STRCMP_CONTAINS("<div id=\"view3d\"", html.c_str());
  // three.js and its orbit controls are in the page itself: nothing is fetched when it opens.
  STRCMP_CONTAINS("REVISION", html.c_str());
  STRCMP_CONTAINS("OrbitControls", html.c_str());
  CHECK(html.find("<script src") == std::string::npos);
  // 50,000 points strided by 3: 16,667 colours (three values each, 0 to 1), the first saturated
  // red (at the range), the rest white.
  const size_t from = html.find("const c=[") + 9, to = html.find("];", from);
  CHECK(from > 9 && to != std::string::npos);
  const std::string values = html.substr(from, to - from);
  LONGS_EQUAL(3 * 16667, std::count(values.begin(), values.end(), ',') + 1);
  STRCMP_CONTAINS("const c=[0.7843,0.1176,0.1176,1.0000,1.0000,1.0000,", html.c_str());
  STRCMP_EQUAL("", view3d_html(Inspection{}, ColourScale{}).c_str());
}

// The surface under the points: the nominal's or the fitted surface's mesh, cropped to the points'
// area and coarsened to what a page carries, its vertices near the surface they came from.
TEST(Report, TheThreeDViewDrawsTheSurfaceCroppedAndCoarsenedUnderThePoints) {
  // A 200 x 200 mm plane z = 0.01 x meshed at 0.5 mm (320,000 triangles); the points cover 40 x 30 mm.
  Mesh plane;
  const int n = 401;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) plane.vertices.push_back({-80 + 0.5 * i, -80 + 0.5 * j, 0.01 * (-80 + 0.5 * i)});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = static_cast<uint32_t>(j * n + i);
      plane.triangles.push_back({a, a + 1, a + n + 1});
      plane.triangles.push_back({a, a + n + 1, a + n});
    }
  Inspection inspection;
  for (int j = 0; j <= 30; ++j)
    for (int i = 0; i <= 40; ++i) inspection.points.push_back({{1.0 * i, 1.0 * j, 0.01 * i}, {1.0 * i, 1.0 * j, 0.01 * i}, 0.0});
  const Mesh view = mesh_for_view(plane, inspection, 4000);
  CHECK(!view.triangles.empty());
  CHECK(view.triangles.size() <= 4000);
  double x0 = HUGE_VAL, x1 = -HUGE_VAL;
  for (const Point3& v : view.vertices) {
    x0 = std::min(x0, v.x), x1 = std::max(x1, v.x);
    DOUBLES_EQUAL(0.01 * v.x, v.z, 1e-9);  // merged vertices are means of vertices on the plane
  }
  // Cropped to the points' box widened by a tenth of its larger side (4 mm), give or take a cell.
  CHECK(x0 > -4 - 3 && x0 < 0);
  CHECK(x1 > 40 && x1 < 44 + 3);
  for (const auto& t : view.triangles) {
    CHECK(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    for (uint32_t k : t) CHECK(k < view.vertices.size());
  }
  // A mesh already small enough comes back cropped only.
  const Mesh small = mesh_for_view(plane, inspection, 1000000);
  CHECK(small.triangles.size() > view.triangles.size());
  ColourScale scale;
  const std::string html = view3d_html(inspection, scale, &view);
  STRCMP_CONTAINS("const st=[", html.c_str());
  STRCMP_CONTAINS("MeshLambertMaterial", html.c_str());
  STRCMP_EQUAL("", view3d_html(Inspection{}, scale, &view).c_str());
  CHECK(mesh_for_view(plane, Inspection{}, 4000).triangles.empty());
}
