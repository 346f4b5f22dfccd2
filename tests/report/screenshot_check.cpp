// Checks a browser's screenshot of an inspection report: the verdict, the histogram and the maps'
// colour scales are on screen as pixels, and the text was drawn. Exit 0 when all hold, 1 with what
// is missing, 2 on bad arguments or an unreadable picture.
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "host/inspect/deviation_map.h"

namespace {

struct Rgb {
  int r, g, b;
};

struct Screenshot {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;

  // Pixels within `within` (largest channel difference) of a colour.
  long count(Rgb c, int within) const {
    long n = 0;
    for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
      n += std::abs(rgb[i] - c.r) <= within && std::abs(rgb[i + 1] - c.g) <= within && std::abs(rgb[i + 2] - c.b) <= within;
    }
    return n;
  }
};

bool read_png(const char* path, Screenshot& out) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path)) return false;
  image.format = PNG_FORMAT_RGB;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgb.resize(PNG_IMAGE_SIZE(image));
  return png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) != 0;
}

// `verify --svg`'s picture of E against L (verify_command.cpp's colours): a length within E_MPE is
// a blue dot, one beyond it a red dot, and E_MPE's two dashed lines are red. A 640 x 400 rendering
// of the simulated plate's 36 lengths; a missing picture or text fails.
int check_verify_picture(const Screenshot& shot, bool pass) {
  const long blue = shot.count({0x24, 0x71, 0xa3}, 6), red = shot.count({0xc0, 0x39, 0x2b}, 6);
  const long text = shot.count({0, 0, 0}, 70);
  struct Expectation {
    const char* what;
    bool ok;
    long pixels;
  };
  const Expectation expectations[] = {
      {pass ? "lengths within E_MPE: blue dots (at least 400)" : "lengths beyond E_MPE: red dots and lines (at least 1200)",
       pass ? blue >= 400 : red >= 1200, pass ? blue : red},
      {pass ? "E_MPE's dashed lines and no red dot (150 to 900 red)" : "E_MPE's dashed lines (at least 150 red)",
       pass ? red >= 150 && red <= 900 : red >= 150, red},
      {"text drawn (at least 400 near-black pixels)", text >= 400, text},
  };
  int failed = 0;
  std::printf("screenshot %d x %d\n", shot.width, shot.height);
  for (const Expectation& e : expectations) {
    std::printf("  %-64s %8ld %s\n", e.what, e.pixels, e.ok ? "ok" : "MISSING");
    failed += !e.ok;
  }
  return failed ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool usage = argc == 3 || (argc == 4 && std::strcmp(argv[3], "first-page") == 0);
  const bool verify = argc == 3 && (std::strcmp(argv[2], "verify-pass") == 0 || std::strcmp(argv[2], "verify-fail") == 0);
  if (!usage || (!verify && std::strcmp(argv[2], "pass") != 0 && std::strcmp(argv[2], "fail") != 0)) {
    std::fprintf(stderr, "usage: screenshot_check SHOT.png pass|fail [first-page] | verify-pass|verify-fail\n");
    return 2;
  }
  // The PDF's first page (rendered by pdftoppm at 100 dpi) holds the verdict, the histogram and text only.
  const bool first_page = argc == 4;
  Screenshot shot;
  if (!read_png(argv[1], shot)) {
    std::fprintf(stderr, "screenshot_check: %s is not a readable PNG\n", argv[1]);
    return 2;
  }
  const bool pass = std::strcmp(argv[2], "pass") == 0;
  if (verify) return check_verify_picture(shot, std::strcmp(argv[2], "verify-pass") == 0);
  // The colours come from the report's own style (html_report.cpp, histogram.cpp, deviation_map.cpp);
  // the thresholds are a fraction of what a 1000 x 4400 px rendering shows, so a missing element fails
  // whatever the fonts' exact metrics.
  const Rgb kPassGreen{0x1a, 0x7f, 0x37}, kFailRed{0xc6, 0x28, 0x28};
  const Rgb kBar{0x4a, 0x78, 0xb5};
  const Rgb kBand{250, 229, 185};  // #f6d48b at 0.6 opacity over white
  // The maps' colour bars: how many of 20 shades from the middle to each saturated end show up as a
  // patch (a broken picture leaves none; a red limit line or red text is only one).
  auto shades = [&](double sign) {
    long present = 0;
    for (int k = 1; k <= 20; ++k) {
      const dg::host::Rgb c = dg::host::diverging_colour(sign * k / 20.0);
      present += shot.count({c.r, c.g, c.b}, 2) >= 40;
    }
    return present;
  };
  struct Expectation {
    const char* what;
    long pixels;
    long at_least;  // -1: at most `at_most`
    long at_most;
  };
  std::vector<Expectation> expectations = {
      {pass ? "the verdict PASS in green" : "the verdict FAIL in red", shot.count(pass ? kPassGreen : kFailRed, 8), 150, -1},
      {"the histogram's bars", shot.count(kBar, 6), 400, -1},
      {"the maps' colour bars: shades of red (of 20)", shades(1), 16, -1},
      {"the maps' colour bars: shades of blue (of 20)", shades(-1), 16, -1},
      {"text drawn (near-black pixels)", shot.count({0, 0, 0}, 70), 5000, -1},
      {"the 3D view's canvas (#f4f5f8)", shot.count({0xf4, 0xf5, 0xf8}, 0), 100000, -1},
  };
  // The deviation map and the 3D view are on the tolerance scale (tolerance_colour): green near the
  // nominal, and the colour bar's blocks for beyond each limit, about 1,100 pixels each at this size.
  // A failing part's points beyond the limits take those colours in the map and the 3D view too; a
  // passing part has none (a point beyond a limit cannot pass), so there the blocks are all.
  const dg::host::Rgb green = dg::host::tolerance_colour(0, -1, 1);
  const long above = shot.count({dg::host::kAboveUpperLimit.r, dg::host::kAboveUpperLimit.g, dg::host::kAboveUpperLimit.b}, 2);
  const long below = shot.count({dg::host::kBelowLowerLimit.r, dg::host::kBelowLowerLimit.g, dg::host::kBelowLowerLimit.b}, 2);
  expectations.push_back({"the tolerance scale: green near the nominal", shot.count({green.r, green.g, green.b}, 2), 2000, -1});
  expectations.push_back({"the tolerance scale: the block above the upper limit", above, 400, -1});
  expectations.push_back({"the tolerance scale: the block below the lower limit", below, 400, -1});
  if (pass) expectations.push_back({"the tolerance scale: no point beyond a limit", above + below, -1, 4000});
  if (!pass) expectations.push_back({"the tolerance scale: points beyond the limits", above + below, 8000, -1});
  if (first_page) {
    expectations.erase(std::remove_if(expectations.begin(), expectations.end(),
                                      [](const Expectation& e) {
                                        return std::strstr(e.what, "colour bars") || std::strstr(e.what, "3D view") ||
                                               std::strstr(e.what, "tolerance scale");
                                      }),
                       expectations.end());
    for (Expectation& e : expectations) e.at_least /= 4;  // a page at 100 dpi holds a quarter of the pixels
  }
  // The limits' red lines are in every histogram; only a failing part's report lacks the green. The
  // bands within U of the limits are a few um wide: visible beside a passing part's deviations, less
  // than a pixel on the millimetres of a failing one's.
  if (!pass) expectations.push_back({"no green PASS", shot.count(kPassGreen, 8), -1, 20});
  if (pass) expectations.push_back({"the histogram's bands within U of the limits", shot.count(kBand, 6), 400, -1});
  int failed = 0;
  std::printf("screenshot %d x %d\n", shot.width, shot.height);
  for (const Expectation& e : expectations) {
    const bool ok = e.at_least >= 0 ? e.pixels >= e.at_least : e.pixels <= e.at_most;
    std::printf("  %-52s %8ld (%s %ld) %s\n", e.what, e.pixels, e.at_least >= 0 ? "at least" : "at most",
                e.at_least >= 0 ? e.at_least : e.at_most, ok ? "ok" : "MISSING");
    failed += !ok;
  }
  return failed ? 1 : 0;
}
