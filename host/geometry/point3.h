// A measured point in millimetres, as the host's point-cloud code handles it.
#pragma once

namespace dg::host {

struct Point3 {
  double x = 0, y = 0, z = 0;  // mm
};

}  // namespace dg::host
