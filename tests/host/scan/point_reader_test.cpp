// Point readers: the columns we know, and an error naming file and line for bad input.
#include "host/scan/point_reader.h"

#include <CppUTest/TestHarness.h>

#include <string>
#include <vector>

namespace {

std::string error_of(const std::string& csv) {
  try {
    dg::host::parse_csv_points(csv, "in.csv");
  } catch (const dg::host::PointFileError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(PointReader){};

TEST(PointReader, ReadsCsvWithOptionalColumnsInAnyOrder) {
  const dg::host::PointCloud c = dg::host::parse_csv_points(
      "z,x,y,line,sigma\n1.5,2,3,0,0.002\n\n-4e-3,5,6,1,0.001\r\n", "in.csv");
  LONGS_EQUAL(2, c.points.size());
  DOUBLES_EQUAL(2.0, c.points[0].x, 0);
  DOUBLES_EQUAL(1.5, c.points[0].z, 0);
  DOUBLES_EQUAL(-0.004, c.points[1].z, 0);
  CHECK(c.line.has_value());
  LONGS_EQUAL(1, (*c.line)[1]);
  CHECK(c.sigma.has_value());
  CHECK_FALSE(c.normal.has_value());
}

TEST(PointReader, ReadsCloudComparesAsciiExportsWithAnySeparator) {
  // "//" before the header, upper-case names, colours and a scalar field to read past.
  const dg::host::PointCloud spaces =
      dg::host::parse_csv_points("//X Y Z R G B Scalar_field\n1.5 2 3 255 0 0 0.7\n4\t5  6 0 255 0 0.1\n", "cc.txt");
  LONGS_EQUAL(2, spaces.points.size());
  DOUBLES_EQUAL(1.5, spaces.points[0].x, 0);
  DOUBLES_EQUAL(6, spaces.points[1].z, 0);
  const dg::host::PointCloud semicolons = dg::host::parse_csv_points("//X;Y;Z;Nx;Ny;Nz\n1;2;3;0;0;1\n", "cc.asc");
  LONGS_EQUAL(1, semicolons.points.size());
  CHECK(semicolons.normal.has_value());
  DOUBLES_EQUAL(1, (*semicolons.normal)[0].z, 0);
  const dg::host::PointCloud commas = dg::host::parse_csv_points("//X,Y,Z\n7,8,9\n", "cc.csv");
  DOUBLES_EQUAL(9, commas.points[0].z, 0);
  // The same as .txt or .xyz: a "//" header is read by its names.
  const dg::host::PointCloud txt = dg::host::parse_xyz_points("//X Y Z R G B\n1 2 3 10 20 30\n", "cc.txt");
  DOUBLES_EQUAL(3, txt.points[0].z, 0);
  // A decimal comma with semicolons is not a number here: said, not guessed.
  STRCMP_CONTAINS("not a finite decimal number: '1,5'", error_of("//X;Y;Z\n1,5;2;3\n").c_str());
}

TEST(PointReader, NamesTheLineOfEveryBadRow) {
  STRCMP_CONTAINS("in.csv:3: column 'z' is not a finite decimal number: 'nan'", error_of("x,y,z\n1,2,3\n1,2,nan\n").c_str());
  STRCMP_CONTAINS("in.csv:2: column 'y' is not a finite decimal number: 'inf'", error_of("x,y,z\n1,inf,3\n").c_str());
  STRCMP_CONTAINS("in.csv:3: 2 values, the header has 3", error_of("x,y,z\n1,2,3\n4,5\n").c_str());
  STRCMP_CONTAINS("in.csv:1: unknown column 'w'", error_of("x,y,z,w\n1,2,3,4\n").c_str());
  STRCMP_CONTAINS("in.csv:1: column 'x' appears twice", error_of("x,y,z,x\n").c_str());
  STRCMP_CONTAINS("in.csv:1: header has no 'z'", error_of("x,y\n1,2\n").c_str());
  STRCMP_CONTAINS("in.csv:3: the same point as in.csv:2", error_of("x,y,z\n1,2,3\n1,2,3\n").c_str());
  STRCMP_CONTAINS("in.csv:2: column 'x' is not a finite decimal number: '1.2.3'", error_of("x,y,z\n1.2.3,2,3\n").c_str());
  STRCMP_CONTAINS("normals need all of nx, ny, nz", error_of("x,y,z,nx\n").c_str());
  STRCMP_CONTAINS("empty file", error_of("").c_str());
}

// Of several repeated points, the one named is the first a reader meets going down the file, with
// the earliest of its copies; 0 and -0 are one point.
TEST(PointReader, NamesTheFirstRepeatInTheFileAndTheEarliestCopyOfIt) {
  STRCMP_CONTAINS("in.csv:5: the same point as in.csv:3", error_of("x,y,z\n1,1,1\n2,2,2\n3,3,3\n2,2,2\n1,1,1\n").c_str());
  STRCMP_CONTAINS("in.csv:4: the same point as in.csv:2", error_of("x,y,z\n1,1,1\n5,5,5\n1,1,1\n1,1,1\n5,5,5\n").c_str());
  STRCMP_CONTAINS("in.csv:4: the same point as in.csv:3", error_of("x,y,z\n9,9,9\n0,1,2\n-0,1,2\n").c_str());
  CHECK(error_of("x,y,z\n1,1,1\n1,1,2\n1,2,1\n2,1,1\n").empty());
}

// A large file is checked in parts by hash on both cores: the repeat named is still the first in
// the file, whichever part it falls in, and a file without one passes.
TEST(PointReader, NamesTheFirstRepeatInALargeFile) {
  std::string csv = "x,y,z\n";
  auto row = [](int i) { return std::to_string(i % 300) + "," + std::to_string(i / 300) + "," + std::to_string(i % 7) + "\n"; };
  for (int i = 0; i < 60000; ++i) csv += row(i);
  CHECK(error_of(csv).empty());
  // Row 60,003 repeats row 30,001, row 60,004 repeats row 11 (file lines are one more: the header).
  csv += row(60000) + row(60001) + row(30000) + row(10);
  STRCMP_CONTAINS("in.csv:60004: the same point as in.csv:30002", error_of(csv).c_str());
}

// A file over a megabyte is parsed in pieces on every core: every row is read, in file order, the
// lines are numbered across the pieces (blank lines and CRLF endings counted), and of two bad rows
// the one named is the first in the file.
TEST(PointReader, ALargeFileReadInPiecesKeepsItsRowsAndLineNumbers) {
  std::string csv = "\r\nx,z,y,line,sigma\r\n";
  std::vector<size_t> line_of_row;
  size_t line = 2;
  for (int i = 0; i < 80000; ++i) {
    if (i % 997 == 0) csv += "\r\n", ++line;  // a blank line now and then
    csv += std::to_string(i % 400) + "," + std::to_string(i) + ".25," + std::to_string(i / 400) + "," + std::to_string(i / 400) +
           ",0.002\r\n";
    line_of_row.push_back(++line);
  }
  CHECK(csv.size() > (size_t{1} << 20));
  const dg::host::PointCloud c = dg::host::parse_csv_points(csv, "in.csv");
  LONGS_EQUAL(80000, c.points.size());
  CHECK(c.line.has_value() && c.sigma.has_value());
  for (size_t i = 0; i < c.points.size(); i += 1) {
    DOUBLES_EQUAL(static_cast<double>(i % 400), c.points[i].x, 0);
    DOUBLES_EQUAL(static_cast<double>(i) + 0.25, c.points[i].z, 0);
    LONGS_EQUAL(i / 400, (*c.line)[i]);
  }
  // Bad rows late in the file and in its first half: the first is named, by its own line.
  std::string bad = csv;
  const std::string late = "399,79999.25,199,199,0.002";
  bad.replace(bad.find(late), late.size(), "399,79999.25,199,199,-1");
  STRCMP_CONTAINS(("in.csv:" + std::to_string(line_of_row[79999]) + ": sigma must be from 0.000001 to 1000000 mm").c_str(), error_of(bad).c_str());
  const std::string early = "\n17,17.25,0,0,0.002";
  bad.replace(bad.find(early), early.size(), "\n17,x,0,0,0.002");
  STRCMP_CONTAINS(("in.csv:" + std::to_string(line_of_row[17]) + ": column 'z' is not a finite decimal number: 'x'").c_str(),
                  error_of(bad).c_str());
}

TEST(PointReader, ReadsWhitespaceXyzAndRefusesShortRows) {
  const dg::host::PointCloud c = dg::host::parse_xyz_points("# comment\n1 2 3\n\t4  5 6\n", "in.xyz");
  LONGS_EQUAL(2, c.points.size());
  DOUBLES_EQUAL(6.0, c.points[1].z, 0);
  try {
    dg::host::parse_xyz_points("1 2 3\n4 5\n", "in.xyz");
    FAIL("short row accepted");
  } catch (const dg::host::PointFileError& e) {
    STRCMP_CONTAINS("in.xyz:2: expected 3 values", e.what());
  }
}

// Numbers are decimal and finite; a denormal is a number; nothing else passes, and an error never
// echoes a huge field or a terminal's escape sequence.
TEST(PointReader, TakesDecimalNumbersOnlyAndQuotesBadFieldsSafely) {
  STRCMP_CONTAINS("in.csv:2: column 'x' is not a finite decimal number: '0x10'", error_of("x,y,z\n0x10,2,3\n").c_str());
  STRCMP_CONTAINS("'1e999'", error_of("x,y,z\n1e999,2,3\n").c_str());
  const dg::host::PointCloud tiny = dg::host::parse_csv_points("x,y,z\n4.9e-324,2,3\n", "in.csv");
  CHECK(tiny.points[0].x > 0);
  STRCMP_CONTAINS("in.csv:2: a NUL byte", error_of(std::string("x,y,z\n1\0junk,2,3\n", 18)).c_str());
  STRCMP_CONTAINS("from 0 to 4294967294", error_of("x,y,z,line\n1,2,3,4294967295\n").c_str());
  const std::string huge(10000000, '7');
  const std::string long_error = error_of("x,y,z\n1," + huge + "x,3\n");
  CHECK(long_error.size() < 300);
  STRCMP_CONTAINS("(cut; 10000001 characters)", long_error.c_str());
  const std::string escape_error = error_of("x,y,z,\x1b[2J\n1,2,3,4\n");
  CHECK(escape_error.find('\x1b') == std::string::npos);
  STRCMP_CONTAINS("\\x1b[2J", escape_error.c_str());
}

// A coordinate or a normal beyond a kilometre, or a sigma below a nanometre or beyond a kilometre,
// is refused with its line: within those the fits' squares and weights stay far from overflow (a z
// of 1e200 made a fit's distances infinite, and a sigma of 1e-12 among 0.001 passed for a hole).
TEST(PointReader, CoordinatesBeyondAKilometreAndSigmasBeyondANanometreToAKilometreAreRefused) {
  STRCMP_CONTAINS("in.csv:3: column 'z' is '1e200': coordinates and normals must lie within +-1000000 mm (1 km)",
                  error_of("x,y,z\n0,0,1\n1,0,1e200\n").c_str());
  STRCMP_CONTAINS("in.csv:2: column 'x' is '-1000000.5'", error_of("x,y,z\n-1000000.5,0,1\n").c_str());
  STRCMP_CONTAINS("in.csv:2: column 'nz' is '1e7'", error_of("x,y,z,nx,ny,nz\n0,0,1,0,0,1e7\n").c_str());
  const dg::host::PointCloud edge = dg::host::parse_csv_points("x,y,z,sigma\n-1000000,1000000,1e6,1e-6\n1,2,3,1e6\n", "in.csv");
  DOUBLES_EQUAL(1e6, edge.points[0].z, 0);
  for (const char* bad : {"1e-12", "9.9e-7", "1000000.5", "0", "-0.001"}) {
    STRCMP_CONTAINS("in.csv:3: sigma must be from 0.000001 to 1000000 mm (1 nm to 1 km)",
                    error_of(std::string("x,y,z,sigma\n0,0,1,0.001\n1,0,1,") + bad + "\n").c_str());
  }
  try {
    dg::host::parse_xyz_points("1 2 3\n4 5 -2e6\n", "in.xyz");
    FAIL("a z of -2e6 mm accepted");
  } catch (const dg::host::PointFileError& e) {
    STRCMP_CONTAINS("in.xyz:2: column 'z' is '-2e6': coordinates and normals", e.what());
  }
}

TEST(PointReader, ALineNumberMustBeAWholeNumberBelowTheNoLineMark) {
  const std::string head = "x,y,z,line\n1,2,3,0\n";
  for (const char* bad : {"-1", "2.5", "4294967295", "1e12"}) {
    STRCMP_CONTAINS("in.csv:3: line must be a whole number from 0 to 4294967294",
                    error_of(head + "4,5,6," + bad + "\n").c_str());
  }
  const dg::host::PointCloud c = dg::host::parse_csv_points(head + "4,5,6,4294967294\n", "in.csv");
  LONGS_EQUAL(4294967294u, (*c.line)[1]);
}
