// Fuzzes the STEP surface reader: damaged files give StepError, never a crash.
#include <string>

#include "host/cad/step_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    dg::host::parse_step_surface(std::string(reinterpret_cast<const char*>(data), size), "fuzz.stp");
  } catch (const dg::host::StepError&) {
  }
  return 0;
}
