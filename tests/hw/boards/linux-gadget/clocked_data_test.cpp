// DATA's level at each CK edge from DATA's timestamped edges, and the cases where that record
// cannot be trusted (so the frame is read again rather than decoded wrong).
#include <CppUTest/TestHarness.h>

#include "hw/boards/linux-gadget/clocked_data.h"

using dg::gadget::ClockedData;

TEST_GROUP(ClockedData) {};

TEST(ClockedData, GivesTheLevelAtEachClockEdgeEvenWhenLaterEdgesAreQueued) {
  ClockedData data(true);
  // Bits 1, 0, 0, 1: DATA changes at the falls (1000, 3000, 7000), CK rises at 2000, 4000, 6000, 8000.
  data.add(3000, false);
  data.add(7000, true);
  CHECK(data.queued_level());
  CHECK(data.level_at(2000));
  CHECK_FALSE(data.level_at(4000));
  CHECK_FALSE(data.level_at(6000));
  CHECK(data.level_at(8000));
  CHECK_FALSE(data.take_doubtful());
}

TEST(ClockedData, AnEdgeReportedTheSameWayTwiceMeansEdgesWereMerged) {
  ClockedData data(false);
  data.add(1000, true);
  data.add(3000, true);  // a fall between them was lost
  CHECK(data.level_at(2000));
  CHECK_FALSE(data.take_doubtful());
  data.level_at(4000);
  CHECK(data.take_doubtful());
  CHECK_FALSE(data.take_doubtful());  // once
}

TEST(ClockedData, AnEdgeThatArrivesAfterTheClockEdgeThatNeededItIsDoubtful) {
  ClockedData data(false);
  CHECK_FALSE(data.level_at(2000));  // answered without the edge at 1500, still on its way
  data.add(1500, true);
  CHECK(data.take_doubtful());
}

TEST(ClockedData, AnOverfullRecordKeepsTheNewestAndIsDoubtful) {
  ClockedData data(false);
  for (int i = 1; i <= 200; ++i) data.add(static_cast<uint64_t>(i) * 10, i % 2 == 1);
  CHECK(data.take_doubtful());
  CHECK_FALSE(data.queued_level());  // the 200th edge: a fall
  CHECK_FALSE(data.level_at(2000));
}

TEST(ClockedData, WithNoEdgesTheLevelIsTheOneItStartedWith) {
  ClockedData data(true);
  CHECK(data.queued_level());
  CHECK(data.level_at(100));
  CHECK_FALSE(data.take_doubtful());
}
