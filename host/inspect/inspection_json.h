// An inspection's summary as JSON: statistics and bands, with what was compared.
#pragma once
#include <string>

#include "host/inspect/inspect.h"

namespace dg::host {

std::string inspection_json_text(const Inspection& inspection, const std::string& points_file, const std::string& surface_file);

}  // namespace dg::host
