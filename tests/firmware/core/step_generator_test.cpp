// Step generation on the simulated table: exact counts, straight lines, rate limits.
#include "firmware/core/step_generator.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <vector>

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

TEST(StepGenerator, NeverAcceleratesFasterThanConfigured) {
  // Step k of a move from rest may not come before sqrt(2 k / a) (constant acceleration a), nor
  // may the last steps come faster than braking to rest allows.
  dg::sim::SimBoard board(dg::sim::SimConfig{}, nullptr);
  std::vector<uint64_t> times;
  board.log_x_steps(&times);
  const dg::MotionConfig config;
  dg::StepGenerator motion(board, config);
  const uint64_t start = board.now_ns();
  CHECK(motion.move_to(2000, 0, 0) == dg::Status::kOk);
  while (motion.busy() && board.wait(UINT64_MAX)) {
  }
  LONGS_EQUAL(2000, times.size());
  const double a = config.accel_steps_s2;
  for (size_t k = 1; k <= times.size(); ++k) {
    const double earliest_ns = 1e9 * std::sqrt(2.0 * static_cast<double>(k) / a);
    CHECK(static_cast<double>(times[k - 1] - start) >= earliest_ns * (1 - 1e-6) - 1);
  }
  const uint64_t end = times.back();
  for (size_t j = 1; j < 400; ++j) {
    // j steps before the end: braking from there to rest takes at least sqrt(2 j / a).
    const double braking_ns = 1e9 * std::sqrt(2.0 * static_cast<double>(j) / a);
    CHECK(static_cast<double>(end - times[times.size() - 1 - j]) >= braking_ns * (1 - 1e-6) - 1);
  }
}

TEST(StepGenerator, ATouchProbeLatchesWhereItTriggersAndBrakesWithinTheOvertravel) {
  // A face at x = 20 mm (8000 steps); probing from 10 mm towards 30 mm at three feeds, with the
  // probe read before each step and through its edge interrupt.
  for (int run = 0; run < 6; ++run) {
    const bool edge = run >= 3;
    const uint32_t rate = run % 3 == 0 ? 400u : run % 3 == 1 ? 2000u : 4000u;
    dg::sim::SimConfig c;
    c.start_x_steps = 4000;
    c.touch_x_steps = 8000;
    dg::sim::SimBoard board(c, nullptr);
    dg::StepGenerator motion(board, dg::MotionConfig{});
    if (edge) motion.attach_probe();
    motion.set_position(4000, 0);
    CHECK(motion.probe_to(12000, 0, rate, 200) == dg::Status::kOk);
    while (motion.busy() && board.wait(UINT64_MAX)) {
    }
    CHECK(motion.touched());
    // Latched at the first step where the stylus is deflected, whatever the feed.
    LONGS_EQUAL(8000, motion.touch_x_steps());
    CHECK(motion.x_steps() >= 8000);
    CHECK(motion.x_steps() <= 8000 + 200);
    LONGS_EQUAL(motion.x_steps(), board.table_x_steps());
  }
  // Too fast to brake within 10 steps: refused before moving.
  dg::sim::SimBoard board(dg::sim::SimConfig{}, nullptr);
  dg::StepGenerator motion(board, dg::MotionConfig{});
  CHECK(motion.probe_to(4000, 0, 8000, 10) == dg::Status::kInvalidArgument);
  // No face in the way: the move ends where it was sent, untouched.
  CHECK(motion.probe_to(400, 0, 400, 10) == dg::Status::kOk);
  while (motion.busy() && board.wait(UINT64_MAX)) {
  }
  CHECK(!motion.touched());
  LONGS_EQUAL(400, motion.x_steps());
}
