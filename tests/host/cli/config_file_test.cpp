// The config file fills only what a command line left out, through the options' own checks, and
// a line it cannot use is an error that names the line.
#include "host/cli/config_file.h"

#include <CLI/CLI.hpp>
#include <CppUTest/TestHarness.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dg::host;

TEST_GROUP(ConfigFile) {
  std::string path;
  CLI::App app{"test", "digitizer"};
  double feed = 10.0;
  unsigned samples = 1;
  double tolerance = 0, upper = 0, lower = 0;
  std::vector<double> bands{0.01, 0.1};
  std::string operator_name;
  void setup() override {
    path = std::string(P_tmpdir) + "/dg_config_file_" + std::to_string(getpid());
    CLI::App* scan = app.add_subcommand("scan");
    scan->add_option("--feed", feed)->check(CLI::Range(0.01, 200.0));
    scan->add_option("--samples", samples)->check(CLI::Range(1, 16));
    CLI::App* inspect = app.add_subcommand("inspect");
    inspect->add_option("--tolerance", tolerance);
    inspect->add_option("--upper", upper);
    inspect->add_option("--lower", lower);
    inspect->add_option("--band", bands);
    inspect->add_option("--operator", operator_name);
  }
  void teardown() override { std::remove(path.c_str()); }
  void write(const char* text) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text, f);
    std::fclose(f);
  }
  void parse(std::vector<std::string> words) {
    std::vector<const char*> argv{"digitizer"};
    for (const std::string& w : words) argv.push_back(w.c_str());
    app.parse(static_cast<int>(argv.size()), argv.data());
    apply_config(app, path);
  }
  std::string error_of(std::vector<std::string> words) {
    try {
      parse(words);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  }
};

TEST(ConfigFile, NoFileIsNoSettings) { LONGS_EQUAL(0, read_config(path).size()); }

TEST(ConfigFile, ItsValuesFillWhatTheCommandLineLeftOut) {
  write("# the bench in room 2\nfeed = 7.5\nsamples=3   # three readings\n");
  parse({"scan", "--samples", "5"});
  DOUBLES_EQUAL(7.5, feed, 0);
  LONGS_EQUAL(5, samples);
}

TEST(ConfigFile, ASettingOfAnotherCommandIsLeftAlone) {
  write("feed = 7.5\ntolerance = 0.02\n");
  parse({"inspect"});
  DOUBLES_EQUAL(10.0, feed, 0);
  DOUBLES_EQUAL(0.02, tolerance, 0);
}

// The calibration every scan is corrected by is the one `status` reports on: the one key fills
// both commands' --calibration, and a command line's own still wins.
TEST(ConfigFile, TheCalibrationFillsScanAndStatus) {
  std::string scan_calibration, status_calibration;
  app.get_subcommand("scan")->add_option("--calibration", scan_calibration);
  app.add_subcommand("status")->add_option("--calibration", status_calibration);
  write("calibration = table.cal.json\n");
  parse({"status"});
  CHECK_EQUAL(std::string("table.cal.json"), status_calibration);
  parse({"scan", "--calibration", "none"});
  CHECK_EQUAL(std::string("none"), scan_calibration);
}

TEST(ConfigFile, UpperAndLowerOnTheCommandLineReplaceTheConfiguredTolerance) {
  write("tolerance = 0.02\n");
  parse({"inspect", "--upper", "0.01", "--lower", "-0.03"});
  DOUBLES_EQUAL(0, tolerance, 0);
  DOUBLES_EQUAL(-0.03, lower, 0);
}

TEST(ConfigFile, AListTakesCommasOrSpaces) {
  write("bands = 0.005, 0.02 0.2\noperator = A. Fitter\n");
  parse({"inspect"});
  LONGS_EQUAL(3, bands.size());
  DOUBLES_EQUAL(0.02, bands[1], 0);
  STRCMP_EQUAL("A. Fitter", operator_name.c_str());
}

TEST(ConfigFile, AValueTheOptionRefusesNamesTheLineAndTheOption) {
  write("\nfeed = 500\n");
  const std::string why = error_of({"scan"});
  STRCMP_CONTAINS(":2: feed = 500 (for scan --feed)", why.c_str());
}

TEST(ConfigFile, AnUnknownKeyIsAnErrorNotIgnored) {
  write("feed = 5\nfed = 5\n");
  const std::string why = error_of({"scan"});
  STRCMP_CONTAINS(":2: `fed` is no setting", why.c_str());
  STRCMP_CONTAINS("known: device, feed", why.c_str());
}

TEST(ConfigFile, ALineWithoutAnEqualsSignOrAValueOrGivenTwiceIsRefused) {
  write("feed 5\n");
  STRCMP_CONTAINS(":1: not a `key = value` line", error_of({"scan"}).c_str());
  write("samples =\n");
  STRCMP_CONTAINS(":1: `samples =` gives no value", error_of({"scan"}).c_str());
  write("samples = 2\nsamples = 4\n");
  STRCMP_CONTAINS(":2: `samples` is set again (first on line 1)", error_of({"scan"}).c_str());
}
