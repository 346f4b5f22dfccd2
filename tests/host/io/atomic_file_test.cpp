// Whole-file outputs: a failure leaves the old file (or none) and no hidden part; links are
// followed, devices written through.
#include "host/io/atomic_file.h"

#include <CppUTest/TestHarness.h>

#include <dirent.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

using namespace dg::host;

namespace {

std::string directory() { return std::string(P_tmpdir) + "/dg_atomic_" + std::to_string(getpid()); }

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

int entries(const std::string& dir) {
  int count = 0;
  if (DIR* d = opendir(dir.c_str())) {
    while (const dirent* e = readdir(d)) count += std::string(e->d_name) != "." && std::string(e->d_name) != "..";
    closedir(d);
  }
  return count;
}

}  // namespace

TEST_GROUP(AtomicFile) {
  std::string dir;
  void setup() override {
    dir = directory();
    mkdir(dir.c_str(), 0755);
  }
  void teardown() override {
    if (DIR* d = opendir(dir.c_str())) {
      while (const dirent* e = readdir(d)) {
        const std::string name = e->d_name;
        if (name != "." && name != "..") std::remove((dir + "/" + name).c_str());
      }
      closedir(d);
    }
    rmdir(dir.c_str());
  }
};

TEST(AtomicFile, ReplacesARegularFileAndKeepsItsPermissions) {
  const std::string path = dir + "/out.csv";
  write_file_atomically(path, "old");
  chmod(path.c_str(), 0600);
  write_file_atomically(path, "new contents");
  STRCMP_EQUAL("new contents", read_all(path).c_str());
  struct stat s {};
  stat(path.c_str(), &s);
  LONGS_EQUAL(0600, s.st_mode & 07777);
  LONGS_EQUAL(1, entries(dir));
}

TEST(AtomicFile, AFailedWriteLeavesTheOldFileAndNoPart) {
  // A file size limit makes the write fail as a full disk would.
  const std::string path = dir + "/big.csv";
  write_file_atomically(path, "the old file");
  rlimit old_limit {};
  getrlimit(RLIMIT_FSIZE, &old_limit);
  void (*old_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = 4096;
  setrlimit(RLIMIT_FSIZE, &small);
  bool threw = false;
  try {
    write_file_atomically(path, std::string(100000, 'x'));
  } catch (const std::runtime_error& e) {
    threw = true;
    STRCMP_CONTAINS("nothing was written", e.what());
  }
  setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  CHECK(threw);
  STRCMP_EQUAL("the old file", read_all(path).c_str());
  LONGS_EQUAL(1, entries(dir));
}

TEST(AtomicFile, FollowsASymbolicLinkAndKeepsIt) {
  const std::string target = dir + "/target.csv", link = dir + "/link.csv";
  CHECK(symlink("target.csv", link.c_str()) == 0);  // dangling until written
  write_file_atomically(link, "through the link");
  struct stat s {};
  CHECK(lstat(link.c_str(), &s) == 0 && S_ISLNK(s.st_mode));
  STRCMP_EQUAL("through the link", read_all(target).c_str());
}

TEST(AtomicFile, WritesThroughADeviceWithoutReplacingIt) {
  write_file_atomically("/dev/null", "discarded");
  struct stat s {};
  CHECK(stat("/dev/null", &s) == 0 && S_ISCHR(s.st_mode));
  // /dev/full fails every write with ENOSPC: said plainly.
  try {
    write_file_atomically("/dev/full", "x");
    FAIL("a write to /dev/full succeeded");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS("the disk is full", e.what());
  }
}

TEST(AtomicFile, AMissingDirectoryIsAnErrorNamingThePath) {
  try {
    write_file_atomically(dir + "/no/such/dir/out.csv", "x");
    FAIL("wrote into a missing directory");
  } catch (const std::runtime_error& e) {
    STRCMP_CONTAINS("out.csv", e.what());
  }
}
