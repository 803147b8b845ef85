/// @file
/// @brief The segment file of `sdfccd query` (segment_file.h): its records from csv_numbers.h, checked as segments.
#include "sdfccd/ccd/segment_file.h"

#include <fstream>

#include "sdfccd/csv_numbers.h"
#include "sdfccd/error.h"

namespace sdfccd {

std::vector<SegmentRecord> parseSegments(std::istream& in, const std::string& name, double defaultSigma) {
  std::vector<SegmentRecord> segments;
  for (const CsvNumberLine& record : parseCsvNumberLines(in, name, kMaxSegments, "segments")) {
    const std::vector<double>& values = record.values;
    if (values.size() != 6 && values.size() != 7) {
      throw Error(record.where + "expected 6 or 7 comma-separated numbers (x0,y0,z0,x1,y1,z1[,sigma]), got " +
                  std::to_string(values.size()));
    }
    segments.push_back({Vec3(values[0], values[1], values[2]), Vec3(values[3], values[4], values[5]),
                        values.size() == 7 ? values[6] : defaultSigma, record.lineNumber});
  }
  return segments;
}

std::vector<SegmentRecord> readSegmentFile(const std::string& path, double defaultSigma) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read segments file '" + path + "'");
  return parseSegments(in, path, defaultSigma);
}

}  // namespace sdfccd
