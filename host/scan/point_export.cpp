// Point cloud writers. Integer nanometres print as exact millimetre decimals.
#include "host/scan/point_export.h"
#include "host/io/atomic_file.h"
#include "host/io/file_name.h"

#include <cerrno>
#include <charconv>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace dg::host {
namespace {

// The file is built in memory (open_memstream) and written in one piece by
// write_file_atomically: a full disk or a crash leaves the old file or none, never a truncated one.
struct Buffer {
  char* data = nullptr;
  size_t size = 0;
  std::FILE* stream = nullptr;
  ~Buffer() {
    if (stream) std::fclose(stream);
    std::free(data);
  }
  std::FILE* get() const { return stream; }
};
using File = std::unique_ptr<Buffer>;

File open_for_writing(const std::string& path, const char*) {
  File file = std::make_unique<Buffer>();
  file->stream = open_memstream(&file->data, &file->size);
  if (!file->stream) throw std::runtime_error(path + ": cannot build the file: " + std::strerror(errno));
  return file;
}

void finish(File file, const std::string& path) {
  const bool failed = std::ferror(file->stream) != 0;
  const bool closed = std::fclose(file->stream) == 0;
  file->stream = nullptr;
  if (failed || !closed) throw std::runtime_error(path + ": cannot build the file (out of memory?)");
  write_file_atomically(path, std::string(file->data, file->size));
}

// "-12.345678" from -12345678 nm, without going through floating point.
void print_mm(std::FILE* f, int32_t nm) {
  const int64_t v = nm;
  const int64_t magnitude = v < 0 ? -v : v;
  std::fprintf(f, "%s%" PRId64 ".%06" PRId64, v < 0 ? "-" : "", magnitude / 1000000,
               magnitude % 1000000);
}

}  // namespace

void write_points_csv(const std::string& path, const std::vector<PointSample>& points, const std::vector<double>* sigma_mm) {
  if (sigma_mm && sigma_mm->size() != points.size()) throw std::invalid_argument(path + ": one sigma per point");
  File f = open_for_writing(path, "w");
  std::fprintf(f->get(), sigma_mm ? "x,y,z,line,sigma\n" : "x,y,z,line\n");
  for (size_t i = 0; i < points.size(); ++i) {
    const PointSample& p = points[i];
    print_mm(f->get(), p.x_nm);
    std::fputc(',', f->get());
    print_mm(f->get(), p.y_nm);
    std::fputc(',', f->get());
    print_mm(f->get(), p.z_nm);
    std::fprintf(f->get(), ",%" PRIu32, p.line);
    // Nanometre resolution, like the coordinates: the uncertainty of a micrometre gauge is kept whole.
    if (sigma_mm) std::fprintf(f->get(), ",%.6f", (*sigma_mm)[i]);
    std::fputc('\n', f->get());
  }
  finish(std::move(f), path);
}

void write_points_xyz(const std::string& path, const std::vector<PointSample>& points) {
  File f = open_for_writing(path, "w");
  for (const PointSample& p : points) {
    print_mm(f->get(), p.x_nm);
    std::fputc(' ', f->get());
    print_mm(f->get(), p.y_nm);
    std::fputc(' ', f->get());
    print_mm(f->get(), p.z_nm);
    std::fputc('\n', f->get());
  }
  finish(std::move(f), path);
}

void write_points_ply(const std::string& path, const std::vector<PointSample>& points) {
  File f = open_for_writing(path, "wb");
  std::fprintf(f->get(),
               "ply\nformat binary_little_endian 1.0\ncomment bench digitizer scan, millimetres\n"
               "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
               "property int line\nend_header\n",
               points.size());
  for (const PointSample& p : points) {
    unsigned char record[28];
    const double xyz[3] = {p.x_nm * 1e-6, p.y_nm * 1e-6, p.z_nm * 1e-6};
    const int32_t line = static_cast<int32_t>(p.line);
    // x86 and ARM hosts are little endian, as the header says; memcpy keeps it exact.
    std::memcpy(record, xyz, sizeof(xyz));
    std::memcpy(record + 24, &line, sizeof(line));
    std::fwrite(record, sizeof(record), 1, f->get());
  }
  finish(std::move(f), path);
}

void write_lines_csv(const std::string& path, const std::vector<Point3>& points,
                     const std::vector<uint32_t>& lines) {
  write_cloud_csv(path, points, &lines);
}

void write_cloud_csv(const std::string& path, const std::vector<Point3>& points, const std::vector<uint32_t>* lines) {
  if (lines && lines->size() != points.size()) throw std::invalid_argument(path + ": one line index per point");
  File f = open_for_writing(path, "w");
  std::fprintf(f->get(), lines ? "x,y,z,line\n" : "x,y,z\n");
  // "%.7f" by std::to_chars, which rounds as printf does in the "C" locale: the same text at a
  // fraction of the cost (fprintf took 0.06 s of filter --lts's 1.3 s on 1e5 points). A line holds
  // three doubles of at most 309 digits before the point each.
  char line[1024];
  for (size_t i = 0; i < points.size(); ++i) {
    char* at = line;
    for (double value : {points[i].x, points[i].y, points[i].z}) {
      if (at != line) *at++ = ',';
      at = std::to_chars(at, line + sizeof line, value, std::chars_format::fixed, 7).ptr;
    }
    if (lines) {
      *at++ = ',';
      at = std::to_chars(at, line + sizeof line, (*lines)[i]).ptr;
    }
    *at++ = '\n';
    std::fwrite(line, 1, static_cast<size_t>(at - line), f->get());
  }
  finish(std::move(f), path);
}

void write_points(const std::string& path, const std::vector<PointSample>& points) {
  write_points(path, points, file_format(path));
}

void write_points(const std::string& path, const std::vector<PointSample>& points, FileFormat format,
                  const std::vector<double>* sigma_mm) {
  switch (format) {
    case FileFormat::kCsv: return write_points_csv(path, points, sigma_mm);
    case FileFormat::kPly: return write_points_ply(path, points);
    case FileFormat::kXyz: return write_points_xyz(path, points);
    default: break;
  }
  throw std::invalid_argument(path + ": unknown point format (use .csv, .xyz or .ply)");
}

}  // namespace dg::host
