#include "drivers/serial_imu/euroc_imu_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace vigs::drivers {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

template <class T>
bool parse(std::string_view s, T& out) {
  s = trim(s);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

std::vector<ImuCsvRow> read_euroc_imu_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<ImuCsvRow> rows;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const std::string_view text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    std::string_view cells[7];
    std::size_t count = 0, start = 0;
    for (std::size_t i = 0; i <= text.size(); ++i) {
      if (i == text.size() || text[i] == ',') {
        if (count < 7) cells[count] = text.substr(start, i - start);
        ++count;
        start = i + 1;
      }
    }
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    if (count != 7) {
      throw std::runtime_error(where + "expected 7 columns (t_ns, w xyz, a xyz), found " +
                               std::to_string(count));
    }
    ImuCsvRow r;
    bool ok = parse(cells[0], r.t_ns);
    for (int k = 0; k < 3; ++k) {
      ok = ok && parse(cells[1 + k], r.gyro_rps[k]) && parse(cells[4 + k], r.accel_mps2[k]);
    }
    if (!ok) throw std::runtime_error(where + "malformed number");
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(r.gyro_rps[k]) || !std::isfinite(r.accel_mps2[k]))
        throw std::runtime_error(where + "value is not finite (w xyz, a xyz must be numbers)");
    }
    r.line = line_no;
    if (!rows.empty() && r.t_ns <= rows.back().t_ns) {
      throw std::runtime_error(where + "timestamp does not increase");
    }
    rows.push_back(r);
  }
  if (rows.empty()) throw std::runtime_error(path + ": no samples");
  return rows;
}

}  // namespace vigs::drivers
