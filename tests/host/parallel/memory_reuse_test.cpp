// The program's restart with huge pages: made for a large input only, once, with the arguments
// kept, and what it starts sees the caller's own GLIBC_TUNABLES; every thread shares one heap,
// restarted or not (run through the memory-probe program beside the tests).
#include "host/parallel/memory_reuse.h"

#include <CppUTest/TestHarness.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace {

// memory-probe's report, run by the shell with `environment` set before it and `arguments` after.
std::string probe(const std::string& environment, const std::string& arguments) {
  char self[4096];
  const ssize_t length = readlink("/proc/self/exe", self, sizeof self - 1);
  if (length <= 0) FAIL("no /proc/self/exe");
  std::string dir(self, static_cast<size_t>(length));
  dir.erase(dir.rfind('/'));
  const std::string command = environment + " '" + dir + "/memory-probe' " + arguments;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) FAIL("popen failed");
  std::string out;
  char buffer[512];
  while (const size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  CHECK_EQUAL(0, pclose(pipe));
  return out;
}

std::string restarted() { return dg::host::huge_pages_asked_for_by_restart() ? "restarted=yes\n" : "restarted=no\n"; }

// Every thread shares one heap, restarted or not (glibc's allocator only).
std::string heaps() { return dg::host::huge_pages_asked_for_by_restart() ? "heaps=one\n" : "heaps=(not glibc's)\n"; }

}  // namespace

TEST_GROUP(MemoryReuse) {
  std::string large;  // a file of kLargeInputBytes: the input of a large job
  void setup() override {
    char name[] = "/tmp/memory-reuse-XXXXXX";
    const int fd = mkstemp(name);
    if (fd < 0) FAIL("mkstemp failed");
    CHECK_EQUAL(0, ftruncate(fd, dg::host::kLargeInputBytes));
    close(fd);
    large = name;
  }
  void teardown() override { unlink(large.c_str()); }
};

TEST(MemoryReuse, TheRestartKeepsTheArgumentsAndLeavesNoTunablesBehindWhereThereWereNone) {
  STRCMP_EQUAL(("tunables=(unset)\nmark=gone\n" + restarted() + heaps() + "arg=" + large + "\narg=two words\n").c_str(),
               probe("env -u GLIBC_TUNABLES -u DIGITIZER_HUGE_PAGES", large + " 'two words'").c_str());
}

TEST(MemoryReuse, TheCallersOwnTunablesAreWhatTheProgramPassesOn) {
  STRCMP_EQUAL(("tunables=glibc.malloc.perturb=0\nmark=gone\n" + restarted() + heaps() + "arg=" + large + "\n").c_str(),
               probe("env -u DIGITIZER_HUGE_PAGES GLIBC_TUNABLES=glibc.malloc.perturb=0", large).c_str());
}

TEST(MemoryReuse, HugePagesZeroMeansNoRestart) {
  STRCMP_EQUAL(("tunables=(unset)\nmark=gone\nrestarted=no\n" + heaps() + "arg=" + large + "\n").c_str(),
               probe("env -u GLIBC_TUNABLES DIGITIZER_HUGE_PAGES=0", large).c_str());
}

TEST(MemoryReuse, AJobWithoutALargeInputIsNotRestarted) {
  // One byte short of large, and arguments that name no file.
  CHECK_EQUAL(0, truncate(large.c_str(), dg::host::kLargeInputBytes - 1));
  STRCMP_EQUAL(("tunables=(unset)\nmark=gone\nrestarted=no\n" + heaps() + "arg=one\narg=" + large + "\n").c_str(),
               probe("env -u GLIBC_TUNABLES -u DIGITIZER_HUGE_PAGES", "one " + large).c_str());
}

TEST(MemoryReuse, TheFilterKeepsAHeapPerThread) {
  // Restarted for its large input all the same, and its threads each in a heap of their own.
  const std::string per_thread =
      dg::host::huge_pages_asked_for_by_restart() ? "heaps=several\n" : "heaps=(not glibc's)\n";
  const std::string expected =
      "tunables=(unset)\nmark=gone\n" + restarted() + per_thread + "arg=per-thread\narg=" + large + "\n";
  STRCMP_EQUAL(expected.c_str(), probe("env -u GLIBC_TUNABLES -u DIGITIZER_HUGE_PAGES", "per-thread " + large).c_str());
}
