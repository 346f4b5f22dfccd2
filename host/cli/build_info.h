// What the build knew about itself (configured by CMake into build_info.cpp).
#pragma once

namespace dg::host {

extern const char kBuildVersion[];  // the project's version
extern const char kBuildCommit[];   // the git commit the build was configured at, or "unknown"
extern const char kBuildType[];     // Release, Debug, ... (empty: CMake's default)

}  // namespace dg::host
