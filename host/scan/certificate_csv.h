// An artefact's certificate as a small CSV: one row of numbers a line, a header line allowed.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace dg::host {

// Each row's `columns` finite numbers, comma-separated; '#' lines and empty lines skipped, a
// first line that is not numbers taken for a header. Throws CalibrationError naming the file and
// line, with `row_words` saying what a row holds ("x_mm,y_mm").
std::vector<std::vector<double>> read_certificate_rows(const std::string& path, size_t columns, const std::string& row_words);
// The same from the file's text; `name` stands for the file in messages.
std::vector<std::vector<double>> parse_certificate_rows(const std::string& text, const std::string& name, size_t columns,
                                                        const std::string& row_words);

}  // namespace dg::host
