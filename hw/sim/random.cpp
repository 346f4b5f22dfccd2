// PCG-XSH-RR 64/32 and Box-Muller; our own so results do not depend on the C++ library.
#include "hw/sim/random.h"

#include <cmath>

namespace dg::sim {

Random::Random(uint64_t seed) : state_(0), increment_((seed << 1u) | 1u) {
  next_u32();
  state_ += 0x853c49e6748fea9bULL ^ seed;
  next_u32();
}

uint32_t Random::next_u32() {
  const uint64_t old = state_;
  state_ = old * 6364136223846793005ULL + increment_;
  const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
  const uint32_t rot = static_cast<uint32_t>(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

double Random::uniform() { return next_u32() * (1.0 / 4294967296.0); }

double Random::gaussian() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u = 0.0;
  do {
    u = uniform();
  } while (u <= 0.0);
  const double v = uniform();
  const double radius = std::sqrt(-2.0 * std::log(u));
  const double angle = 6.283185307179586 * v;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

}  // namespace dg::sim
