// What a command prints on standard output, captured through a file for a test to read.
#pragma once
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace dg::test {

// Runs `run()` with standard output (or the descriptor `fd`: 2 for standard error) sent to the file
// `capture`; returns what it printed (the file is removed) and leaves run()'s result in `result`.
// The descriptor comes back even when run() throws: else the test runner's own report of the
// failure would go into the file.
template <class Run, class Result>
std::string printed_by(Run run, const std::string& capture, Result& result, int fd = 1) {
  struct Redirect {
    int fd, saved, file;
    Redirect(const std::string& path, int which)
        : fd(which),
          saved((std::fflush(nullptr), dup(which))),
          file(open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644)) {
      dup2(file, fd);
    }
    ~Redirect() {
      std::fflush(nullptr);
      dup2(saved, fd);
      close(saved), close(file);
    }
  };
  {
    const Redirect to_file(capture, fd);
    result = run();
  }
  std::ifstream in(capture);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(capture.c_str());
  return text.str();
}

}  // namespace dg::test
