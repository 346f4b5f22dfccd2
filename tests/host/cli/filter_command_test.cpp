// filter's lists: every point the filter could not judge is written, with its measured height, to a
// file beside the output (the terminal shows only the first few), and each stays in the output.
#include "host/cli/filter_command.h"

#include <CppUTest/TestHarness.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <string>
#include <tuple>

#include "host/scan/lts_filter.h"
#include "host/scan/point_export.h"
#include "host/scan/point_reader.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

namespace {

using Key = std::tuple<double, double, double>;
Key key_of(const Point3& p) { return {p.x, p.y, p.z}; }

std::set<Key> keys_of(const std::vector<Point3>& points) {
  std::set<Key> out;
  for (const Point3& p : points) out.insert(key_of(p));
  return out;
}

bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }

}  // namespace

TEST_GROUP(FilterCommand) {
  std::string base;
  void setup() override { base = std::string(P_tmpdir) + "/dg_filter_" + std::to_string(getpid()); }
  void teardown() override {
    for (const char* suffix : {".in.csv", ".out.csv", ".out.outliers.csv", ".out.unjudged.csv", ".listed.csv"}) {
      std::remove((base + suffix).c_str());
    }
  }
  FilterArgs args_for(const dg::test::PartScan& s) {
    write_cloud_csv(base + ".in.csv", dg::test::scan_part(s, 1).points, nullptr);
    FilterArgs a;
    a.input = base + ".in.csv";
    a.output = base + ".out.csv";
    return a;
  }
};

TEST(FilterCommand, EveryPointNotJudgedIsListedInAFileBesideTheOutputAndKept) {
  // The reference sphere's foot is steeper than a 1 mm grid resolves: the filter keeps points there
  // unjudged, more of them than the terminal shows.
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kSphere;
  s.sigma_um = 2;
  const FilterArgs a = args_for(s);
  const PointCloud input = read_points(a.input);
  const LtsResult expected = lts_filter(input.points, a.options);
  CHECK(expected.unjudged.size() > 5);

  LONGS_EQUAL(0, run_filter(a));
  CHECK(exists(base + ".out.unjudged.csv"));
  const std::vector<Point3> listed = read_points(base + ".out.unjudged.csv").points;
  LONGS_EQUAL(expected.unjudged.size(), listed.size());
  std::set<Key> want;
  for (size_t i : expected.unjudged) want.insert(key_of(input.points[i]));
  CHECK(want == keys_of(listed));
  // Kept as measured: each listed point is in the filtered output with its own height.
  const std::set<Key> kept = keys_of(read_points(a.output).points);
  for (const Point3& p : listed) CHECK(kept.count(key_of(p)) == 1);
}

TEST(FilterCommand, TheListOfPointsNotJudgedGoesWhereItIsNamed) {
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kSphere;
  s.sigma_um = 2;
  FilterArgs a = args_for(s);
  a.unjudged = base + ".listed.csv";
  LONGS_EQUAL(0, run_filter(a));
  CHECK(exists(base + ".listed.csv"));
  CHECK(!exists(base + ".out.unjudged.csv"));
  CHECK(!read_points(base + ".listed.csv").points.empty());
}

TEST(FilterCommand, AScanWhoseEveryPointIsJudgedWritesNoListOfThem) {
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kSaddle;
  s.sigma_um = 2;
  const FilterArgs a = args_for(s);
  LONGS_EQUAL(0, run_filter(a));
  CHECK(exists(a.output));
  CHECK(!exists(base + ".out.unjudged.csv"));
}

TEST(FilterCommand, FewerPointsThanTheSmallestWindowAreRefusedWithTheirCount) {
  // Four points: no window to judge any of them by. Nine (one 3 x 3 window) are filtered.
  std::vector<Point3> points = {{0, 0, 1}, {1, 0, 1.001}, {0, 1, 0.999}, {1, 1, 1.002}};
  write_cloud_csv(base + ".in.csv", points, nullptr);
  FilterArgs a;
  a.input = base + ".in.csv";
  a.output = base + ".out.csv";
  try {
    run_filter(a);
    FAIL("four points filtered");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS(": 4 points: the LTS filter needs at least 9 (one 3 x 3 window)", e.what());
  }
  CHECK(!exists(base + ".out.csv"));
  for (int k = 0; k < 5; ++k) points.push_back({2.0, static_cast<double>(k % 3) + (k < 3 ? 0 : 0.5), 1.0});
  write_cloud_csv(base + ".in.csv", points, nullptr);
  LONGS_EQUAL(0, run_filter(a));
  CHECK(exists(base + ".out.csv"));
}
