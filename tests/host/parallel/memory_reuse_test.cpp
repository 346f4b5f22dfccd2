// The program's restart with huge pages: it happens once, keeps the arguments, and gives what it
// starts the caller's own GLIBC_TUNABLES (run through the memory-probe program beside the tests).
#include "host/parallel/memory_reuse.h"

#include <CppUTest/TestHarness.h>

#include <cstdio>
#include <string>
#include <unistd.h>

namespace {

// memory-probe's report, run by the shell with `environment` set before it.
std::string probe(const std::string& environment) {
  char self[4096];
  const ssize_t length = readlink("/proc/self/exe", self, sizeof self - 1);
  if (length <= 0) FAIL("no /proc/self/exe");
  std::string dir(self, static_cast<size_t>(length));
  dir.erase(dir.rfind('/'));
  const std::string command = environment + " '" + dir + "/memory-probe' one 'two words'";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) FAIL("popen failed");
  std::string out;
  char buffer[512];
  while (const size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  CHECK_EQUAL(0, pclose(pipe));
  return out;
}

std::string restarted() { return dg::host::huge_pages_asked_for_by_restart() ? "restarted=yes\n" : "restarted=no\n"; }

}  // namespace

TEST_GROUP(MemoryReuse){};

TEST(MemoryReuse, TheRestartKeepsTheArgumentsAndLeavesNoTunablesBehindWhereThereWereNone) {
  STRCMP_EQUAL(("tunables=(unset)\nmark=gone\n" + restarted() + "arg=one\narg=two words\n").c_str(),
               probe("env -u GLIBC_TUNABLES -u DIGITIZER_HUGE_PAGES").c_str());
}

TEST(MemoryReuse, TheCallersOwnTunablesAreWhatTheProgramPassesOn) {
  STRCMP_EQUAL(("tunables=glibc.malloc.perturb=0\nmark=gone\n" + restarted() + "arg=one\narg=two words\n").c_str(),
               probe("env -u DIGITIZER_HUGE_PAGES GLIBC_TUNABLES=glibc.malloc.perturb=0").c_str());
}

TEST(MemoryReuse, HugePagesZeroMeansNoRestart) {
  STRCMP_EQUAL("tunables=(unset)\nmark=gone\nrestarted=no\narg=one\narg=two words\n",
               probe("env -u GLIBC_TUNABLES DIGITIZER_HUGE_PAGES=0").c_str());
}
