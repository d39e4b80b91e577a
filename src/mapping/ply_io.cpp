#include "mapping/ply_io.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "io/atomic_file.hpp"

namespace vigs::mapping {

namespace {

const char* const kProps[] = {"x",       "y",      "z",      "nx",      "ny",      "nz",
                              "f_dc_0",  "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1",
                              "scale_2", "rot_0",  "rot_1",  "rot_2",   "rot_3"};
constexpr int kNumProps = 17;

bool little_endian_host() {
  const std::uint16_t v = 1;
  unsigned char b;
  std::memcpy(&b, &v, 1);
  return b == 1;
}

}  // namespace

std::size_t write_gaussian_ply(const std::string& path, const GaussianMap& map) {
  if (!little_endian_host()) throw PlyError(path + ": big-endian hosts are not supported");
  std::size_t written = 0;
  for (std::size_t i = 0; i < map.size(); ++i) written += map.finite(i) ? 1 : 0;
  try {
    io::write_file_atomically(path, [&](std::FILE* f) {
      std::string header =
          "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(written) + "\n";
      for (const char* p : kProps) header += std::string("property float ") + p + "\n";
      header += "end_header\n";
      std::fwrite(header.data(), 1, header.size(), f);
      float row[kNumProps];
      const float c0 = static_cast<float>(kShC0);
      for (std::size_t i = 0; i < map.size(); ++i) {
        if (!map.finite(i)) continue;
        for (int k = 0; k < 3; ++k) {
          row[k] = map.mean_w[3 * i + k];
          row[3 + k] = 0.0f;
          row[6 + k] = (map.color_rgb[3 * i + k] - 0.5f) / c0;
          row[10 + k] = map.log_scale[3 * i + k];
        }
        row[9] = map.opacity_logit[i];
        for (int k = 0; k < 4; ++k) row[13 + k] = map.quat_wxyz[4 * i + k];
        std::fwrite(row, sizeof(float), kNumProps, f);
      }
    });
  } catch (const std::runtime_error& e) {
    throw PlyError(e.what());
  }
  return map.size() - written;
}

GaussianMap read_gaussian_ply(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw PlyError(path + ": cannot open for reading");
  std::string line;
  int line_no = 0;
  auto next_line = [&]() -> bool {
    if (!std::getline(f, line)) return false;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  auto fail = [&](const std::string& what) -> PlyError {
    return PlyError(path + ": header line " + std::to_string(line_no) + ": " + what);
  };
  if (!next_line() || line != "ply") throw fail("not a PLY file (missing 'ply' magic)");
  std::size_t count = 0;
  bool in_vertex = false, seen_vertex = false, binary_le = false;
  std::vector<std::string> props;
  std::vector<int> sizes;
  while (true) {
    if (!next_line()) throw fail("unexpected end of file before end_header");
    std::istringstream ss(line);
    std::string kw;
    ss >> kw;
    if (kw == "end_header") break;
    if (kw == "format") {
      std::string fmt;
      ss >> fmt;
      if (fmt != "binary_little_endian")
        throw fail("format '" + fmt + "' is not supported (need binary_little_endian)");
      binary_le = true;
    } else if (kw == "element") {
      std::string name;
      ss >> name;
      in_vertex = name == "vertex";
      if (in_vertex) {
        // The whole word must be a count: `element vertex abc` is an error, not 0 vertices.
        std::string word, extra;
        ss >> word;
        std::uint64_t n = 0;
        const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), n);
        if (word.empty() || ec != std::errc() || end != word.data() + word.size() || (ss >> extra))
          throw fail("vertex count '" + word + "' is not a non-negative integer");
        if (seen_vertex) throw fail("a second 'element vertex'");
        count = static_cast<std::size_t>(n);
        seen_vertex = true;
      } else if (seen_vertex) {
        throw fail("elements after 'vertex' are not supported");
      }
    } else if (kw == "property") {
      if (!in_vertex) continue;
      std::string type, name;
      ss >> type >> name;
      if (type == "list") throw fail("list properties in 'vertex' are not supported");
      int size = 0;
      if (type == "float" || type == "float32")
        size = 4;
      else if (type == "double" || type == "float64")
        size = 8;
      else if (type == "uchar" || type == "uint8" || type == "char" || type == "int8")
        size = 1;
      else if (type == "short" || type == "ushort" || type == "int16" || type == "uint16")
        size = 2;
      else if (type == "int" || type == "uint" || type == "int32" || type == "uint32")
        size = 4;
      else
        throw fail("unknown property type '" + type + "'");
      props.push_back(type + " " + name);
      sizes.push_back(size);
    }
  }
  if (!binary_le) throw fail("missing 'format' line");
  if (!seen_vertex) throw fail("no 'vertex' element");
  // locate the 17 required float properties
  std::map<std::string, int> offset_of;
  int stride = 0;
  for (std::size_t k = 0; k < props.size(); ++k) {
    const auto sp = props[k].find(' ');
    const std::string type = props[k].substr(0, sp), name = props[k].substr(sp + 1);
    if (type == "float" || type == "float32") offset_of[name] = stride;
    stride += sizes[k];
  }
  int offs[kNumProps];
  for (int k = 0; k < kNumProps; ++k) {
    auto it = offset_of.find(kProps[k]);
    if (it == offset_of.end())
      throw PlyError(path + ": missing float vertex property '" + kProps[k] + "'");
    offs[k] = it->second;
  }
  const std::streamoff data_start = f.tellg();
  f.seekg(0, std::ios::end);
  const std::streamoff data_bytes = f.tellg() - data_start;
  f.seekg(data_start);
  if (static_cast<std::uintmax_t>(data_bytes) / static_cast<std::uintmax_t>(stride) < count)
    throw PlyError(path + ": header promises " + std::to_string(count) + " vertices of " +
                   std::to_string(stride) + " bytes but only " + std::to_string(data_bytes) +
                   " bytes follow the header at byte " + std::to_string(data_start) +
                   " (truncated at byte " +
                   std::to_string(data_start + data_bytes / stride * stride) + ")");
  GaussianMap map;
  map.resize(count);
  std::vector<char> row(static_cast<std::size_t>(stride));
  const float c0 = static_cast<float>(kShC0);
  for (std::size_t i = 0; i < count; ++i) {
    f.read(row.data(), stride);
    if (!f)
      throw PlyError(path + ": truncated at byte " +
                     std::to_string(data_start + static_cast<std::streamoff>(i) * stride) +
                     " (vertex " + std::to_string(i) + " of " + std::to_string(count) + ")");
    float v[kNumProps];
    for (int k = 0; k < kNumProps; ++k) {
      std::memcpy(&v[k], row.data() + offs[k], 4);
      if (!std::isfinite(v[k]))
        throw PlyError(
            path + ": vertex " + std::to_string(i) + " property '" + kProps[k] +
            "' is not finite (byte " +
            std::to_string(data_start + static_cast<std::streamoff>(i) * stride + offs[k]) + ")");
    }
    for (int k = 0; k < 3; ++k) {
      map.mean_w[3 * i + k] = v[k];
      map.color_rgb[3 * i + k] = 0.5f + c0 * v[6 + k];
      map.log_scale[3 * i + k] = v[10 + k];
    }
    map.opacity_logit[i] = v[9];
    for (int k = 0; k < 4; ++k) map.quat_wxyz[4 * i + k] = v[13 + k];
  }
  return map;
}

}  // namespace vigs::mapping
