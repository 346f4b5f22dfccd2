// A device command's device: --device, else DIGITIZER_DEVICE, else the config file; never a silent
// simulator.
#include "host/cli/device_choice.h"

#include <CppUTest/TestHarness.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

using namespace dg::host;

TEST_GROUP(DeviceChoice) {
  std::string dir;
  std::string saved_device, saved_xdg;
  bool had_device = false, had_xdg = false;
  void setup() override {
    dir = std::string(P_tmpdir) + "/dg_config_" + std::to_string(getpid());
    mkdir(dir.c_str(), 0755);
    mkdir((dir + "/digitizer").c_str(), 0755);
    if (const char* d = std::getenv("DIGITIZER_DEVICE")) had_device = true, saved_device = d;
    if (const char* x = std::getenv("XDG_CONFIG_HOME")) had_xdg = true, saved_xdg = x;
    unsetenv("DIGITIZER_DEVICE");
    setenv("XDG_CONFIG_HOME", dir.c_str(), 1);
  }
  void teardown() override {
    std::remove((dir + "/digitizer/config").c_str());
    rmdir((dir + "/digitizer").c_str());
    rmdir(dir.c_str());
    if (had_device) setenv("DIGITIZER_DEVICE", saved_device.c_str(), 1);
    else unsetenv("DIGITIZER_DEVICE");
    if (had_xdg) setenv("XDG_CONFIG_HOME", saved_xdg.c_str(), 1);
    else unsetenv("XDG_CONFIG_HOME");
  }
  void write_config(const char* text) {
    std::FILE* f = std::fopen((dir + "/digitizer/config").c_str(), "w");
    std::fputs(text, f);
    std::fclose(f);
  }
};

TEST(DeviceChoice, WithoutAnyChoiceItRefusesAndSaysHowToChoose) {
  try {
    chosen_device("");
    FAIL("a device was chosen from nothing");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("--device", e.what());
    STRCMP_CONTAINS("DIGITIZER_DEVICE", e.what());
    STRCMP_CONTAINS((dir + "/digitizer/config").c_str(), e.what());
  }
}

TEST(DeviceChoice, TheOptionWinsThenTheEnvironmentThenTheConfigFile) {
  write_config("# the bench\n  device = usb:serial=BENCH-1  # the left one\n");
  STRCMP_EQUAL("usb:serial=BENCH-1", chosen_device("").c_str());
  setenv("DIGITIZER_DEVICE", "unix:/tmp/x.sock", 1);
  STRCMP_EQUAL("unix:/tmp/x.sock", chosen_device("").c_str());
  STRCMP_EQUAL("sim:part=flat", chosen_device("sim:part=flat").c_str());
}

TEST(DeviceChoice, AConfigLineThatNamesNothingIsAnErrorWithItsLine) {
  write_config("\n\ndevice =\n");
  try {
    chosen_device("");
    FAIL("an empty device line was accepted");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("config:3", e.what());
  }
}

TEST(DeviceChoice, TheConfigFileGivesTheReportsOperatorAndCompany) {
  write_config("device = sim:part=dome\noperator = A. Fitter   # the bench in room 2\ncompany=Small Works Ltd\n");
  STRCMP_EQUAL("A. Fitter", configured_value(config_path(), "operator").c_str());
  STRCMP_EQUAL("Small Works Ltd", configured_value(config_path(), "company").c_str());
  STRCMP_EQUAL("", configured_value(config_path(), "serial").c_str());
}
