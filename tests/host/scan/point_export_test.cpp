// Point export: exact millimetre text, a PLY whose header matches its body.
#include "host/scan/point_export.h"

#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace {

std::string temp_path(const char* name) {
  return std::string(P_tmpdir) + "/dg_test_" + std::to_string(getpid()) + "_" + name;
}

std::vector<dg::PointSample> sample_points() {
  std::vector<dg::PointSample> points(3);
  points[0].x_nm = 1500000;
  points[0].y_nm = -1;
  points[0].z_nm = -12345678;
  points[1].x_nm = 0;
  points[1].line = 1;
  points[2].x_nm = 2147483647;
  points[2].line = 2;
  return points;
}

}  // namespace

TEST_GROUP(PointExport){};

TEST(PointExport, CsvIsExactToTheNanometre) {
  const std::string path = temp_path("p.csv");
  dg::host::write_points(path, sample_points());
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  STRCMP_EQUAL(
      "x,y,z,line\n1.500000,-0.000001,-12.345678,0\n0.000000,0.000000,0.000000,1\n"
      "2147.483647,0.000000,0.000000,2\n",
      text.str().c_str());
  std::remove(path.c_str());
}

// A scan's per-point uncertainty goes into the CSV as the sigma column the readers take back.
TEST(PointExport, CsvCarriesEachPointsSigmaWhenGiven) {
  const std::string path = temp_path("s.csv");
  const std::vector<double> sigma = {0.0058, 0.0058, 0.0091};
  dg::host::write_points(path, sample_points(), dg::host::FileFormat::kCsv, &sigma);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  STRCMP_EQUAL(
      "x,y,z,line,sigma\n1.500000,-0.000001,-12.345678,0,0.005800\n0.000000,0.000000,0.000000,1,0.005800\n"
      "2147.483647,0.000000,0.000000,2,0.009100\n",
      text.str().c_str());
  const std::vector<double> short_sigma = {0.1};
  CHECK_THROWS(std::invalid_argument, dg::host::write_points(path, sample_points(), dg::host::FileFormat::kCsv, &short_sigma));
  std::remove(path.c_str());
}

TEST(PointExport, XyzIsExactAndReadsBack) {
  const std::string path = temp_path("p.xyz");
  dg::host::write_points(path, sample_points());
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  STRCMP_EQUAL("1.500000 -0.000001 -12.345678\n0.000000 0.000000 0.000000\n2147.483647 0.000000 0.000000\n",
               text.str().c_str());
  std::remove(path.c_str());
}

TEST(PointExport, PlyHeaderMatchesBody) {
  const std::string path = temp_path("p.ply");
  dg::host::write_points(path, sample_points());
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t end = bytes.find("end_header\n");
  CHECK(end != std::string::npos);
  CHECK(bytes.find("element vertex 3") != std::string::npos);
  LONGS_EQUAL(3 * 28, bytes.size() - (end + 11));
  double x = 0;
  std::memcpy(&x, bytes.data() + end + 11, sizeof(x));
  DOUBLES_EQUAL(1.5, x, 1e-12);
  std::remove(path.c_str());
}

TEST(PointExport, RefusesAnUnknownExtension) {
  CHECK_THROWS(std::invalid_argument, dg::host::write_points(temp_path("p.txt"), sample_points()));
}

TEST(PointExport, ReportsAnUnwritablePath) {
  CHECK_THROWS(std::runtime_error, dg::host::write_points("/nonexistent-dir/p.csv", sample_points()));
}

// A cloud's CSV prints each coordinate as printf's "%.7f" would, halfway cases and negative zero
// included, with the line column when the cloud has one.
TEST(PointExport, CloudCsvPrintsSevenDecimalsAsPrintfDoes) {
  const std::vector<dg::host::Point3> points = {
      {-0.0, 2.5e-8, -1.5e-7}, {0.12345675, 1e6 / 3, -2147.4836475}, {1e12, -1e-300, 0.999999951}};
  const std::vector<uint32_t> lines = {0, 7, 4294967295u};
  for (const std::vector<uint32_t>* with : {static_cast<const std::vector<uint32_t>*>(nullptr), &lines}) {
    const std::string path = temp_path("c.csv");
    dg::host::write_cloud_csv(path, points, with);
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    std::string expected = with ? "x,y,z,line\n" : "x,y,z\n";
    for (size_t i = 0; i < points.size(); ++i) {
      char line[1024];
      std::snprintf(line, sizeof line, "%.7f,%.7f,%.7f", points[i].x, points[i].y, points[i].z);
      expected += line;
      if (with) expected += "," + std::to_string(lines[i]);
      expected += "\n";
    }
    STRCMP_EQUAL(expected.c_str(), text.str().c_str());
    std::remove(path.c_str());
  }
}
