// Man pages and bash completion made from a command tree: every listed subcommand and option is
// in them, unlisted ones are not, and help text that roff would take for requests stays text.
#include "host/cli/self_description.h"

#include <CppUTest/TestHarness.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace {

struct Tree {
  Tree() : app("a test tool", "digitizer") {
    CLI::App* fit = app.add_subcommand("fit", ".fit' a surface: the first help line begins with a dot");
    fit->add_option("-o,--output", output, "file");
    fit->add_option("--tolerance", tolerance, ".5 starts a roff request; a \\ backslash; -- dashes");
    CLI::App* hidden = app.add_subcommand("secret", "not for users");
    hidden->group("");
  }
  CLI::App app;
  std::string output;
  double tolerance = 0;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_GROUP(SelfDescription){};

TEST(SelfDescription, CompletionOffersListedSubcommandsAndTheirOptionsOnly) {
  Tree tree;
  const std::string script = dg::host::bash_completion(tree.app);
  STRCMP_CONTAINS("compgen -W \"fit ", script.c_str());
  STRCMP_CONTAINS("fit) opts=\"--help -h --output -o --tolerance\"", script.c_str());
  CHECK(script.find("secret") == std::string::npos);
  STRCMP_CONTAINS("complete -o filenames -F _digitizer digitizer", script.c_str());
}

TEST(SelfDescription, ManPagesKeepHelpTextAsTextAndListEverySubcommand) {
  Tree tree;
  char directory[] = "/tmp/digitizer-man-XXXXXX";
  CHECK(mkdtemp(directory) != nullptr);
  LONGS_EQUAL(2, dg::host::write_man_pages(tree.app, directory));
  const std::string main_page = slurp(std::string(directory) + "/digitizer.1");
  const std::string fit_page = slurp(std::string(directory) + "/digitizer-fit.1");
  STRCMP_CONTAINS(".TH DIGITIZER 1", main_page.c_str());
  STRCMP_CONTAINS("\\fBdigitizer\\-fit\\fR(1)", main_page.c_str());
  CHECK(main_page.find("secret") == std::string::npos);
  STRCMP_CONTAINS(".TH DIGITIZER-FIT 1", fit_page.c_str());
  STRCMP_CONTAINS("\\-\\-tolerance", fit_page.c_str());
  STRCMP_CONTAINS("a \\e backslash", fit_page.c_str());
  STRCMP_CONTAINS("\\&.fit' a surface", fit_page.c_str());
  // No help line begins with a dot or an apostrophe that roff would read as a request.
  std::istringstream lines(fit_page);
  std::string line;
  bool in_text = false;
  while (std::getline(lines, line)) {
    if (line == ".nf") in_text = true;
    else if (line == ".fi") in_text = false;
    else if (in_text) CHECK_TEXT(line.empty() || (line[0] != '.' && line[0] != '\''), line.c_str());
  }
  std::remove((std::string(directory) + "/digitizer.1").c_str());
  std::remove((std::string(directory) + "/digitizer-fit.1").c_str());
  rmdir(directory);
}

TEST(SelfDescription, TheVersionNamesCommitProtocolAndBuild) {
  const std::string version = dg::host::version_text();
  STRCMP_CONTAINS("digitizer ", version.c_str());
  STRCMP_CONTAINS("(commit ", version.c_str());
  STRCMP_CONTAINS(", protocol ", version.c_str());
}
