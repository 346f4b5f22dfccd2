// Finding a program the digitizer starts (Chromium, dfu-util, openocd) on the PATH.
#pragma once
#include <string>

namespace dg::host {

// The first executable `name` in $PATH's directories (/usr/bin:/bin without PATH); "" if none.
std::string find_on_path(const std::string& name);

}  // namespace dg::host
