// The report as a PDF for sign-off: the HTML printed by headless Chromium, the same content a
// browser shows.
#pragma once
#include <string>

namespace dg::host {

// Prints `html_path` to `pdf_path` (written whole or not at all) with Chromium: $DIGITIZER_CHROMIUM,
// else `chromium` or `chromium-browser` on the PATH. Returns "" when written, else why not (no
// Chromium, it failed, it took over two minutes, or what it wrote is no PDF).
std::string print_pdf(const std::string& html_path, const std::string& pdf_path);

// Chromium's path: $DIGITIZER_CHROMIUM, else `chromium` or `chromium-browser` on the PATH; "" if none.
std::string find_chromium();

// The file: URL of an absolute path, every byte but RFC 3986's unreserved ones and '/' percent-encoded,
// so a '#', '?', '%' or space in a folder's name is part of the path and not a fragment or a query.
std::string file_url(const std::string& absolute_path);

}  // namespace dg::host
