// The deviation files: the PLY's header names the scalar field, a PLY reader reads the points back
// exactly, and each record's float holds the deviation.
#include "host/inspect/deviation_file.h"

#include <CppUTest/TestHarness.h>

#include <cstring>

#include "host/scan/ply_reader.h"

using namespace dg::host;

namespace {

std::vector<PointDeviation> three() {
  return {{{1.25, 2.5, 3.125}, {}, 0.0125}, {{-4, 5.000001, 6}, {}, -0.25}, {{7, 8, 9.999999}, {}, 0, true}};
}

}  // namespace

TEST_GROUP(DeviationFile){};

TEST(DeviationFile, TheCsvHasOneLinePerPoint) {
  STRCMP_EQUAL("x,y,z,deviation,beyond_edge\n1.250000,2.500000,3.125000,0.012500,0\n-4.000000,5.000001,6.000000,-0.250000,0\n"
               "7.000000,8.000000,9.999999,0.000000,1\n",
               format_deviations_csv(three()).c_str());
}

TEST(DeviationFile, ThePlyReadsBackWithItsScalarField) {
  const std::string bytes = format_deviations_ply(three());
  STRCMP_CONTAINS("property float scalar_deviation\nproperty uchar scalar_beyond_edge\nend_header\n", bytes.c_str());
  const PointCloud cloud = parse_ply_points(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "d.ply");
  LONGS_EQUAL(3, cloud.points.size());
  DOUBLES_EQUAL(5.000001, cloud.points[1].y, 0);
  DOUBLES_EQUAL(9.999999, cloud.points[2].z, 0);
  const size_t body = bytes.find("end_header\n") + 11;
  LONGS_EQUAL(body + 3 * 29, bytes.size());
  float deviation = 0;
  std::memcpy(&deviation, bytes.data() + body + 29 + 24, sizeof deviation);
  DOUBLES_EQUAL(-0.25, deviation, 0);
  LONGS_EQUAL(0, bytes[body + 29 + 28]);
  LONGS_EQUAL(1, bytes[body + 2 * 29 + 28]);
}
