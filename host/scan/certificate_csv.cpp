// Certificate rows: the line loop every artefact's certificate shares.
#include "host/scan/certificate_csv.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include "host/io/whole_file.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

std::vector<std::vector<double>> read_certificate_rows(const std::string& path, size_t columns, const std::string& row_words) {
  std::string text;
  if (!read_whole_file(path, &text)) throw CalibrationError(path + ": cannot open: " + std::strerror(errno));
  return parse_certificate_rows(text, path, columns, row_words);
}

std::vector<std::vector<double>> parse_certificate_rows(const std::string& text, const std::string& path, size_t columns,
                                                        const std::string& row_words) {
  std::vector<std::vector<double>> out;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<double> row(columns);
    std::istringstream fields(line);
    bool ok = true;
    for (size_t c = 0; c < columns && ok; ++c) {
      char comma = ',';
      ok = (c == 0 || ((fields >> comma) && comma == ',')) && static_cast<bool>(fields >> row[c]);
    }
    char extra = 0;
    if (!ok || (fields >> extra)) {
      if (number == 1 && out.empty()) continue;  // a header
      throw CalibrationError(path + ":" + std::to_string(number) + ": expected " + row_words + ", got '" + line + "'");
    }
    for (double v : row) {
      if (!std::isfinite(v)) throw CalibrationError(path + ":" + std::to_string(number) + ": not a finite number");
    }
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace dg::host
