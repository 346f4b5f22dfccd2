// Deterministic random numbers (PCG32, O'Neill 2014) so one seed gives the same scan everywhere.
#pragma once
#include <cstdint>

namespace dg::sim {

class Random {
 public:
  explicit Random(uint64_t seed);
  uint32_t next_u32();
  double uniform();   // [0, 1)
  double gaussian();  // mean 0, standard deviation 1 (Box-Muller)

 private:
  uint64_t state_;
  uint64_t increment_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace dg::sim
