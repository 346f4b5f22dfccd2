// Fuzzes the IGES surface reader: damaged files give IgesError, never a crash.
#include <string>

#include "host/cad/iges_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    dg::host::parse_iges_surface(std::string(reinterpret_cast<const char*>(data), size), "fuzz.igs");
  } catch (const dg::host::IgesError&) {
  }
  return 0;
}
