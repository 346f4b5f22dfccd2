// doctor's udev check: a rule where udev reads it is ok; one left in an install prefix that udev
// does not read, or none, is a warning that says how to put it in place.
#include "host/cli/doctor_command.h"

#include <CppUTest/TestHarness.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>

using namespace dg::host;

TEST_GROUP(DoctorUdevRule) {
  std::string root, etc, prefix;
  void setup() override {
    root = std::string(P_tmpdir) + "/dg_doctor_" + std::to_string(getpid());
    etc = root + "/etc";
    prefix = root + "/prefix";
    mkdir(root.c_str(), 0755);
    mkdir(etc.c_str(), 0755);
    mkdir(prefix.c_str(), 0755);
  }
  void teardown() override {
    for (const std::string& d : {etc, prefix}) {
      std::remove((d + "/70-bench-digitizer.rules").c_str());
      std::remove((d + "/99-other.rules").c_str());
      rmdir(d.c_str());
    }
    rmdir(root.c_str());
  }
  void write_rule(const std::string& directory, const char* name, const char* text) {
    std::FILE* f = std::fopen((directory + "/" + name).c_str(), "w");
    std::fputs(text, f);
    std::fclose(f);
  }
  static constexpr const char* kRule = "SUBSYSTEM==\"usb\", ATTR{idVendor}==\"1209\", ATTR{idProduct}==\"0001\", TAG+=\"uaccess\"\n";
};

TEST(DoctorUdevRule, ARuleWhereUdevReadsItIsOk) {
  write_rule(etc, "70-bench-digitizer.rules", kRule);
  const Finding f = udev_rule_finding({root + "/none", etc}, prefix, 0x1209, 0x0001);
  CHECK_TRUE(f.verdict == Health::kOk);
  STRCMP_CONTAINS("/etc/70-bench-digitizer.rules", f.what.c_str());
}

TEST(DoctorUdevRule, ARuleOnlyInTheInstallPrefixSaysToCopyIt) {
  write_rule(prefix, "70-bench-digitizer.rules", kRule);
  const Finding f = udev_rule_finding({etc}, prefix, 0x1209, 0x0001);
  CHECK_TRUE(f.verdict == Health::kWarning);
  STRCMP_CONTAINS("where udev does not read it", f.what.c_str());
  STRCMP_CONTAINS("udevadm control --reload", f.fix.c_str());
}

TEST(DoctorUdevRule, ARuleForOtherIdsDoesNotCount) {
  write_rule(etc, "99-other.rules", "SUBSYSTEM==\"usb\", ATTR{idVendor}==\"0483\", ATTR{idProduct}==\"df11\"\n");
  const Finding f = udev_rule_finding({etc}, prefix, 0x1209, 0x0001);
  CHECK_TRUE(f.verdict == Health::kWarning);
  STRCMP_CONTAINS("no udev rule for 1209:0001", f.what.c_str());
  STRCMP_CONTAINS("install-udev-rule", f.fix.c_str());
}
