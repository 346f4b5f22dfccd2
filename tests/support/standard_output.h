// What a command prints on standard output, captured through a file for a test to read.
#pragma once
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace dg::test {

// Runs `run()` with standard output sent to the file `capture`; returns what it printed (the file is
// removed) and leaves run()'s result in `result`.
// Standard output comes back even when run() throws: else the test runner's own report of the
// failure would go into the file.
template <class Run, class Result>
std::string printed_by(Run run, const std::string& capture, Result& result) {
  struct Redirect {
    int saved, file;
    explicit Redirect(const std::string& path)
        : saved((std::fflush(stdout), dup(1))), file(open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644)) {
      dup2(file, 1);
    }
    ~Redirect() {
      std::fflush(stdout);
      dup2(saved, 1);
      close(saved), close(file);
    }
  };
  {
    const Redirect to_file(capture);
    result = run();
  }
  std::ifstream in(capture);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(capture.c_str());
  return text.str();
}

}  // namespace dg::test
