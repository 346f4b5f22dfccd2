// Step generation on the simulated table: exact counts, straight lines, rate limits.
#include "firmware/core/step_generator.h"

#include <CppUTest/TestHarness.h>

#include "hw/sim/sim_board.h"

namespace {

void run_to_end(dg::sim::SimBoard& board, dg::StepGenerator& motion) {
  while (motion.busy()) {
    if (!board.wait(UINT64_MAX)) break;
  }
}

}  // namespace

TEST_GROUP(StepGenerator){};

TEST(StepGenerator, IntegerSquareRoot) {
  for (uint64_t v : {0ull, 1ull, 2ull, 3ull, 4ull, 15ull, 16ull, 17ull, 1000000ull, 4294967295ull,
                     18446744073709551615ull}) {
    const uint64_t r = dg::isqrt64(v);
    CHECK(r * r <= v);
    CHECK((r + 1) * (r + 1) > v || r == 4294967295ull);
  }
}

TEST(StepGenerator, ReachesTheTargetWithExactStepCounts) {
  dg::sim::SimBoard board(dg::sim::SimConfig{}, nullptr);
  dg::StepGenerator motion(board, dg::MotionConfig{});
  const int32_t targets[][2] = {{4000, 0}, {4000, 1234}, {17, 1234}, {0, 0}, {5, 3}};
  uint64_t expected_steps = 0;
  int32_t x = 0, y = 0;
  for (const auto& t : targets) {
    CHECK(motion.move_to(t[0], t[1], 0) == dg::Status::kOk);
    run_to_end(board, motion);
    expected_steps += static_cast<uint64_t>(std::abs(t[0] - x) + std::abs(t[1] - y));
    x = t[0];
    y = t[1];
    LONGS_EQUAL(t[0], motion.x_steps());
    LONGS_EQUAL(t[1], motion.y_steps());
    LONGS_EQUAL(t[0], board.table_x_steps());
    LONGS_EQUAL(t[1], board.table_y_steps());
  }
  CHECK(board.step_count() == expected_steps);
}

TEST(StepGenerator, NeverStepsFasterThanTheMaximumRate) {
  dg::sim::SimBoard board(dg::sim::SimConfig{}, nullptr);
  dg::MotionConfig config;
  dg::StepGenerator motion(board, config);
  CHECK(motion.move_to(20000, 7000, 0) == dg::Status::kOk);
  run_to_end(board, motion);
  const uint64_t shortest_ns = 1000000000ull / config.max_rate_steps_s;
  CHECK(board.min_step_interval_ns() >= shortest_ns);
}

TEST(StepGenerator, RefusesAMoveOutsideTheTableBeforeMoving) {
  dg::sim::SimBoard board(dg::sim::SimConfig{}, nullptr);
  dg::MotionConfig config;
  dg::StepGenerator motion(board, config);
  CHECK(motion.move_to(config.x_max_steps + 1, 0, 0) == dg::Status::kInvalidArgument);
  CHECK(motion.move_to(0, -1, 0) == dg::Status::kInvalidArgument);
  CHECK_FALSE(motion.busy());
  CHECK(board.step_count() == 0);
}

TEST(StepGenerator, RefusesANewMoveWhileMoving) {
  dg::sim::SimBoard board(dg::sim::SimConfig{}, nullptr);
  dg::StepGenerator motion(board, dg::MotionConfig{});
  CHECK(motion.move_to(1000, 0, 0) == dg::Status::kOk);
  CHECK(motion.move_to(0, 0, 0) == dg::Status::kBusy);
  run_to_end(board, motion);
}
