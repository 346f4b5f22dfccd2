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
template <class Run, class Result>
std::string printed_by(Run run, const std::string& capture, Result& result) {
  std::fflush(stdout);
  const int saved = dup(1), file = open(capture.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  dup2(file, 1);
  result = run();
  std::fflush(stdout);
  dup2(saved, 1);
  close(saved), close(file);
  std::ifstream in(capture);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(capture.c_str());
  return text.str();
}

}  // namespace dg::test
