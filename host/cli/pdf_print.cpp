// Runs headless Chromium without a shell (posix_spawn), in a profile of its own that is removed
// afterwards, and checks what it printed before it replaces the PDF.
#include "host/cli/pdf_print.h"
#include "host/cli/program_path.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace dg::host {

namespace {

// Runs Chromium with `arguments` (stdin, stdout and stderr on /dev/null); "" when it exits 0.
std::string run(const std::string& chromium, std::vector<std::string> arguments) {
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t child = 0;
  const int spawned = posix_spawn(&child, chromium.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return chromium + " could not be started";
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      return "Chromium took over two minutes";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? "" : "Chromium failed";
}

}  // namespace

std::string find_chromium() {
  if (const char* chosen = std::getenv("DIGITIZER_CHROMIUM"); chosen && *chosen) return chosen;
  for (const char* name : {"chromium", "chromium-browser"}) {
    const std::string found = find_on_path(name);
    if (!found.empty()) return found;
  }
  return "";
}

std::string file_url(const std::string& absolute_path) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string url = "file://";
  for (const unsigned char c : absolute_path) {
    const bool unreserved = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' ||
                            c == '.' || c == '_' || c == '~' || c == '/';
    if (unreserved) {
      url += static_cast<char>(c);
    } else {
      url += '%';
      url += kHex[c >> 4];
      url += kHex[c & 15];
    }
  }
  return url;
}

std::string print_pdf(const std::string& html_path, const std::string& pdf_path) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) return "Chromium was not found (install Debian's chromium package, or set DIGITIZER_CHROMIUM)";
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path html = fs::absolute(html_path, error);
  char profile_template[] = "/tmp/digitizer-pdf.XXXXXX";
  if (error || !mkdtemp(profile_template)) return "no temporary profile for Chromium could be made";
  const std::string profile = profile_template;
  const std::string part = pdf_path + ".part";
  // No network, nothing fetched in the background; the sandbox cannot start as root. The 3D view
  // draws with WebGL, here on the CPU through SwiftShader on any machine (Chromium asks for the
  // opt-in for software WebGL, given because the page is our own file).
  std::vector<std::string> arguments = {chromium, "--headless", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                                        "--disable-quic", "--no-first-run",
                                        "--disable-background-networking", "--disable-component-update", "--disable-sync",
                                        "--no-pdf-header-footer", "--user-data-dir=" + profile, "--print-to-pdf=" + part,
                                        file_url(html.string())};
  if (geteuid() == 0) arguments.insert(arguments.begin() + 1, "--no-sandbox");
  std::string why = run(chromium, arguments);
  // Where the sandbox cannot start (a container without user namespaces) Chromium fails at once;
  // the page is our own file, so it is printed again without the sandbox.
  if (!why.empty() && geteuid() != 0) {
    arguments.insert(arguments.begin() + 1, "--no-sandbox");
    why = run(chromium, arguments);
  }
  if (why.empty()) {
    std::ifstream in(part, std::ios::binary);
    char magic[5] = {};
    in.read(magic, 5);
    if (std::string(magic, 5) != "%PDF-") why = "Chromium wrote no PDF";
  }
  if (why.empty()) {
    fs::rename(part, pdf_path, error);
    if (error) why = "the PDF could not be put in place: " + error.message();
  }
  fs::remove(part, error);
  fs::remove_all(profile, error);
  return why;
}

}  // namespace dg::host
