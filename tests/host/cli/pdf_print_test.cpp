// The report's file: URL for Chromium: a path's special characters stay part of the path.
#include "host/cli/pdf_print.h"

#include <CppUTest/TestHarness.h>

TEST_GROUP(FileUrl){};

TEST(FileUrl, APlainPathIsUnchanged) {
  STRCMP_EQUAL("file:///home/ann/part-7_v2.0~/report.html", dg::host::file_url("/home/ann/part-7_v2.0~/report.html").c_str());
}

TEST(FileUrl, AHashAQuestionMarkAPercentAndASpaceAreEncoded) {
  STRCMP_EQUAL("file:///jobs/%2312%20mould/50%25%3F/r.html", dg::host::file_url("/jobs/#12 mould/50%?/r.html").c_str());
}

TEST(FileUrl, BytesOfAUtf8NameAreEncodedOneByOne) {
  STRCMP_EQUAL("file:///m%C3%BCller/r.html", dg::host::file_url("/m\xC3\xBCller/r.html").c_str());
}
