// The fitting core never allocates: CppUTest's operator new, with a counting allocator, watches a fit.
#include <CppUTest/TestHarness.h>
#include <CppUTest/MemoryLeakWarningPlugin.h>
#include <CppUTest/TestMemoryAllocator.h>

#include "common/fit/height_field_fit.h"

namespace {
long g_allocations = 0;

class CountingAllocator : public TestMemoryAllocator {
 public:
  char* alloc_memory(size_t size, const char* file, size_t line) override {
    ++g_allocations;
    return TestMemoryAllocator::alloc_memory(size, file, line);
  }
};

// Routes operator new through CppUTest's overloads into the counting allocator while it lives.
class CountAllocations {
 public:
  CountAllocations() {
    g_allocations = 0;
    previous_ = getCurrentNewAllocator();
    MemoryLeakWarningPlugin::turnOnDefaultNotThreadSafeNewDeleteOverloads();
    setCurrentNewAllocator(&counter_);
  }
  ~CountAllocations() {
    setCurrentNewAllocator(previous_);
    MemoryLeakWarningPlugin::turnOffNewDeleteOverloads();
  }

 private:
  CountingAllocator counter_;
  TestMemoryAllocator* previous_;
};
}  // namespace

using namespace dg::fit;

TEST_GROUP(FitCoreAllocation){};

TEST(FitCoreAllocation, AFixedAndADoubleFitAllocateNothing) {
  static HeightFieldFit<FixedPolicy<15>, UniformCubicBasis<5>> fixed_fit;
  static HeightFieldFit<FloatingPolicy<double>, BezierBasis> double_fit;
  static decltype(fixed_fit)::Workspace fixed_work;
  static decltype(double_fit)::Workspace double_work;
  int32_t fixed_heights[5][5];
  double double_heights[4][4];
  dg::Status a, b;
  {
  CountAllocations counting;
  const FitRegion region{0, 50000000, 0, 40000000};
  fixed_fit.begin(region);
  double_fit.begin(region);
  for (int32_t y = 0; y <= 40; ++y)
    for (int32_t x = 0; x <= 50; ++x) {
      fixed_fit.add(x * 1000000, y * 1000000, (x * x - y * y) * 1000);
      double_fit.add(x * 1000000, y * 1000000, (x * x - y * y) * 1000);
    }
  a = fixed_fit.solve(fixed_heights, fixed_work);
  b = double_fit.solve(double_heights, double_work);
  }
  CHECK(dg::Status::kOk == a);
  CHECK(dg::Status::kOk == b);
  LONGS_EQUAL(0, g_allocations);
}

TEST(FitCoreAllocation, TheCounterSeesAnAllocation) {
  {
    CountAllocations counting;
    int* p = new int(3);
    delete p;
  }
  LONGS_EQUAL(1, g_allocations);
}
