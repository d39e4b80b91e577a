#include "inertial/euroc_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

namespace vigs::inertial {

namespace {

constexpr std::array<const char*, 7> kImuFields = {"timestamp", "w_x", "w_y", "w_z",
                                                   "a_x",       "a_y", "a_z"};
constexpr std::array<const char*, 17> kGtFields = {
    "timestamp", "p_x", "p_y",   "p_z",   "q_w",   "q_x",   "q_y",   "q_z",  "v_x",
    "v_y",       "v_z", "b_w_x", "b_w_y", "b_w_z", "b_a_x", "b_a_y", "b_a_z"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

[[noreturn]] void fail(const std::string& name, std::size_t line, std::string_view field,
                       const std::string& message) {
  std::ostringstream os;
  os << name << ":" << line << ": ";
  if (!field.empty()) os << "field '" << field << "': ";
  os << message;
  throw EurocCsvError(os.str());
}

// Splits one data line into exactly N numeric fields: the first an integer stamp, the rest
// finite doubles.
template <std::size_t N>
void parse_line(std::string_view line, const std::string& name, std::size_t line_no,
                const std::array<const char*, N>& fields, std::int64_t& t_ns,
                std::array<double, N>& values) {
  std::size_t k = 0;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = line.find(',', pos);
    const std::string_view tok = trim(
        line.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos));
    if (k >= N) {
      fail(name, line_no, "", "too many fields (expected " + std::to_string(N) + ")");
    }
    if (tok.empty()) fail(name, line_no, fields[k], "empty value");
    const char* first = tok.data();
    const char* last = tok.data() + tok.size();
    if (k == 0) {
      const auto res = std::from_chars(first, last, t_ns);
      if (res.ec != std::errc() || res.ptr != last || t_ns < 0) {
        fail(name, line_no, fields[k],
             "'" + std::string(tok) + "' is not a non-negative integer nanosecond stamp");
      }
    } else {
      double v = 0.0;
      const auto res = std::from_chars(first, last, v);
      if (res.ec != std::errc() || res.ptr != last || !std::isfinite(v)) {
        fail(name, line_no, fields[k], "'" + std::string(tok) + "' is not a finite number");
      }
      values[k] = v;
    }
    ++k;
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  if (k != N) {
    fail(name, line_no, fields[k],
         "missing (line has " + std::to_string(k) + " fields, expected " + std::to_string(N) + ")");
  }
}

// Calls on_row(line_no, t_ns, values) for every data line, checking increasing stamps.
template <std::size_t N, class OnRow>
void for_each_row(const std::string& text, const std::string& name,
                  const std::array<const char*, N>& fields, OnRow on_row) {
  std::size_t line_no = 0;
  std::size_t pos = 0;
  std::int64_t prev_t_ns = -1;
  const std::string_view all(text);
  while (pos < all.size()) {
    std::size_t nl = all.find('\n', pos);
    if (nl == std::string_view::npos) nl = all.size();
    const std::string_view line = trim(all.substr(pos, nl - pos));
    pos = nl + 1;
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    std::int64_t t_ns = 0;
    std::array<double, N> values{};
    parse_line<N>(line, name, line_no, fields, t_ns, values);
    if (t_ns <= prev_t_ns) {
      fail(name, line_no, fields[0],
           "stamp " + std::to_string(t_ns) + " does not increase (previous " +
               std::to_string(prev_t_ns) + ")");
    }
    prev_t_ns = t_ns;
    on_row(line_no, t_ns, values);
  }
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw EurocCsvError(path + ": cannot open for reading");
  std::ostringstream os;
  os << in.rdbuf();
  if (in.bad()) throw EurocCsvError(path + ": read error");
  return os.str();
}

}  // namespace

std::vector<ImuSample> parse_euroc_imu_csv(const std::string& text, const std::string& name) {
  std::vector<ImuSample> out;
  for_each_row<7>(text, name, kImuFields,
                  [&](std::size_t, std::int64_t t_ns, const std::array<double, 7>& v) {
                    ImuSample s;
                    s.t_ns = t_ns;
                    for (int k = 0; k < 3; ++k) {
                      s.gyro_rps[k] = v[static_cast<std::size_t>(1 + k)];
                      s.accel_mps2[k] = v[static_cast<std::size_t>(4 + k)];
                    }
                    out.push_back(s);
                  });
  if (out.empty()) throw EurocCsvError(name + ": no data lines");
  return out;
}

std::vector<GroundTruthState> parse_euroc_groundtruth_csv(const std::string& text,
                                                          const std::string& name) {
  std::vector<GroundTruthState> out;
  for_each_row<17>(text, name, kGtFields,
                   [&](std::size_t line_no, std::int64_t t_ns, const std::array<double, 17>& v) {
                     GroundTruthState g;
                     g.t_ns = t_ns;
                     g.p_w_b_m = {v[1], v[2], v[3]};
                     const Eigen::Quaterniond q(v[4], v[5], v[6], v[7]);  // w x y z
                     if (std::abs(q.norm() - 1.0) > 1e-2) {
                       fail(name, line_no, "q_w",
                            "quaternion (w x y z) norm " + std::to_string(q.norm()) + " is not 1");
                     }
                     g.q_w_b = q.normalized();
                     g.v_w_b_mps = {v[8], v[9], v[10]};
                     g.bias_gyro_rps = {v[11], v[12], v[13]};
                     g.bias_accel_mps2 = {v[14], v[15], v[16]};
                     out.push_back(g);
                   });
  if (out.empty()) throw EurocCsvError(name + ": no data lines");
  return out;
}

std::vector<ImuSample> read_euroc_imu_csv(const std::string& path) {
  return parse_euroc_imu_csv(read_file(path), path);
}

std::vector<GroundTruthState> read_euroc_groundtruth_csv(const std::string& path) {
  return parse_euroc_groundtruth_csv(read_file(path), path);
}

}  // namespace vigs::inertial
