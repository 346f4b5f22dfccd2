// Finding a program the digitizer starts (Chromium, dfu-util, openocd) on the PATH.
#pragma once
#include <string>

namespace dg::host {

// The first executable `name` in $PATH's directories (/usr/bin:/bin without PATH); "" if none.
std::string find_on_path(const std::string& name);

// The prefix this program runs from: /usr for /usr/bin/digitizer ("" when unknown), where the
// packaged udev rule and firmware images lie beside it.
std::string own_prefix();

}  // namespace dg::host
