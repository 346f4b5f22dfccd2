// The module that holds OpenCASCADE: its file, where the digitizer looks for it, and its entry points.
#pragma once
#include <string>

namespace dg::host {
class CadNominal;
}

// The kernel's libraries load in about 40 ms, at every start of every program that links them, for a
// dozen commands of which only `inspect` against a STEP or IGES nominal (and `doctor`) use them; a
// large job starts twice (memory_reuse.h). So they are linked into a module of their own, which the
// program loads when a command first reads such a nominal.
namespace dg::host::cad_module {

// The module's file name, looked for in `lib/digitizer` under the program's own prefix (own_prefix.h:
// the build tree's and the installed package's layout alike), then in the directory it was
// installed to.
constexpr const char* kFileName = "digitizer-occt.so";

// Its entry points, found by name. Nothing thrown crosses them.
// Reads the nominal at *path; on failure nullptr, with the reason in *error.
using ReadNominal = dg::host::CadNominal* (*)(const std::string* path, std::string* error);
constexpr const char* kReadNominal = "dg_cad_read_nominal";
// The OpenCASCADE version it was built with.
using OpencascadeVersion = const char* (*)();
constexpr const char* kOpencascadeVersion = "dg_cad_opencascade_version";

}  // namespace dg::host::cad_module
