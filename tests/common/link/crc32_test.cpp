// CRC-32 against the standard check value and incremental use.
#include "common/link/crc32.h"

#include <CppUTest/TestHarness.h>

#include <cstring>

TEST_GROUP(Crc32){};

TEST(Crc32, MatchesTheStandardCheckValue) {
  const char* text = "123456789";
  LONGS_EQUAL(0xCBF43926u, dg::crc32(reinterpret_cast<const uint8_t*>(text), std::strlen(text)));
}

TEST(Crc32, ContinuesAcrossChunks) {
  const uint8_t data[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  const uint32_t whole = dg::crc32(data, sizeof(data));
  const uint32_t split = dg::crc32_update(dg::crc32(data, 4), data + 4, sizeof(data) - 4);
  LONGS_EQUAL(whole, split);
}

TEST(Crc32, OfNothingIsZero) { LONGS_EQUAL(0u, dg::crc32(nullptr, 0)); }
