// Why a fit cannot be made from the given points: degenerate or insufficient data, bad options.
#pragma once
#include <stdexcept>

namespace dg::host {

class FitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace dg::host
