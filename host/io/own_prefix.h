// Where the running program is installed: the prefix its packaged files lie under.
#pragma once
#include <string>

namespace dg::host {

// The prefix this program runs from: /usr for /usr/bin/digitizer, the build tree for its bin/
// ("" when /proc cannot say). The packaged udev rule, firmware images and the CAD kernel's module
// lie under it.
std::string own_prefix();

}  // namespace dg::host
