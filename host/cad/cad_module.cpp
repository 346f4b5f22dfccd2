// Loading the OpenCASCADE module on first use, and the CAD nominal's entry points through it.
#include "host/cad/cad_module.h"

#include <dlfcn.h>

#include <mutex>
#include <vector>

#include "host/cad/cad_nominal.h"
#include "host/io/own_prefix.h"

namespace dg::host {
namespace {

// The module's handle, loaded once (never closed: the parts it made live until the program ends),
// or the reason it could not be.
struct Loaded {
  void* handle = nullptr;
  std::string problem;
};

const Loaded& loaded() {
  static Loaded module;
  static std::once_flag once;
  std::call_once(once, [] {
    std::vector<std::string> paths;
    if (const std::string prefix = own_prefix(); !prefix.empty()) {
      paths.push_back(prefix + "/lib/digitizer/" + cad_module::kFileName);
    }
    paths.push_back(std::string(DIGITIZER_MODULE_DIR) + "/" + cad_module::kFileName);
    std::string tried;
    for (const std::string& path : paths) {
      module.handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (module.handle) return;
      const char* why = dlerror();
      tried += (tried.empty() ? "" : "; ") + std::string(why ? why : path + ": cannot be loaded");
    }
    module.problem = "the CAD kernel's module (OpenCASCADE, " + std::string(cad_module::kFileName) +
                     ") cannot be loaded: " + tried + " (a broken installation? reinstall the digitizer package)";
  });
  return module;
}

// Entry point `name` of the module; throws CadNominalError when it or the module is missing.
void* entry(const char* name) {
  const Loaded& module = loaded();
  if (!module.handle) throw CadNominalError(module.problem);
  void* at = dlsym(module.handle, name);
  if (!at) {
    throw CadNominalError("the CAD kernel's module " + std::string(cad_module::kFileName) + " has no entry point " +
                          name);
  }
  return at;
}

}  // namespace

std::unique_ptr<CadNominal> CadNominal::read(const std::string& path) {
  const auto read = reinterpret_cast<cad_module::ReadNominal>(entry(cad_module::kReadNominal));
  std::string error;
  std::unique_ptr<CadNominal> part(read(&path, &error));
  if (!part) throw CadNominalError(error.empty() ? path + ": OpenCASCADE could not read it" : error);
  return part;
}

std::string opencascade_version() {
  return reinterpret_cast<cad_module::OpencascadeVersion>(entry(cad_module::kOpencascadeVersion))();
}

}  // namespace dg::host
