#include "xsens_test_stream.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "drivers/serial_imu/xsens_encoder.hpp"

namespace vigs::drivers::test {
namespace {

bool has_inner_header(const std::vector<std::uint8_t>& msg) {
  for (std::size_t i = 1; i + 1 < msg.size(); ++i) {
    if (msg[i] == xsens::kPreamble && msg[i + 1] == xsens::kBusIdMaster) return true;
  }
  return false;
}

// Rounds to float32. The volatile works around GCC 12.2 at -O2, whose SLP vectoriser dropped the
// double -> float -> double round trip for some lanes of the loop below (seen on Debian 12).
double f32(double v) {
  volatile float f = static_cast<float>(v);
  return static_cast<double>(f);
}

}  // namespace

std::vector<std::uint8_t> encode(const TestSample& s) {
  return xsens::encode_mtdata2(s.sample_time_fine, s.accel_mps2, s.gyro_rps);
}

std::vector<TestSample> euroc_samples(std::size_t count, std::uint32_t stf0,
                                      std::uint32_t ticks_per_sample) {
  const std::string path = std::string(VIGS_SHARED_DATA_DIR) + "/euroc_v102/imu0.csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<TestSample> out;
  std::string line;
  std::uint32_t stf = stf0;
  while (out.size() < count && std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    double v[7];
    for (double& x : v) {
      std::getline(ss, cell, ',');
      x = std::stod(cell);
    }
    TestSample s;
    s.sample_time_fine = stf;
    for (int i = 0; i < 3; ++i) {
      s.gyro_rps[i] = f32(v[1 + i]);
      s.accel_mps2[i] = f32(v[4 + i]);
    }
    for (int tries = 0; has_inner_header(encode(s)); ++tries) {
      if (tries > 100) throw std::logic_error("cannot avoid an inner header");
      for (int i = 0; i < 3; ++i) {
        s.gyro_rps[i] = f32(s.gyro_rps[i] * (1.0 + 3e-7));
        s.accel_mps2[i] = f32(s.accel_mps2[i] * (1.0 + 3e-7));
      }
    }
    out.push_back(s);
    stf += ticks_per_sample;
  }
  if (out.size() < count) throw std::runtime_error(path + ": fewer samples than requested");
  return out;
}

void FaultyStreamBuilder::push(std::vector<std::uint8_t> bytes, std::uint32_t stf) {
  if (cut_) throw std::logic_error("nothing may follow cut_off()");
  size_ += bytes.size();
  segments_.push_back({std::move(bytes), stf});
}

void FaultyStreamBuilder::good(const TestSample& s) {
  auto msg = encode(s);
  counts_.packets_ok += 1;
  counts_.bytes_in_messages += msg.size();
  if (!survivors_.empty() && lost_run_ > 0) {
    counts_.sample_counter_gap += 1;
    counts_.samples_missed += lost_run_;
  }
  lost_run_ = 0;
  survivors_.push_back(s);
  push(std::move(msg), s.sample_time_fine);
}

void FaultyStreamBuilder::garbage(std::size_t n, std::uint32_t stf) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<std::uint8_t> g(n);
  for (std::size_t i = 0; i < n; ++i) {
    // No preamble, and no bus id first (a preceding segment may end in 0xFA).
    do {
      g[i] = static_cast<std::uint8_t>(byte(rng_));
    } while (g[i] == xsens::kPreamble || (i == 0 && g[i] == xsens::kBusIdMaster));
  }
  counts_.resync_bytes_skipped += n;
  push(std::move(g), stf);
}

void FaultyStreamBuilder::flipped(const TestSample& s) {
  auto msg = encode(s);
  std::uniform_int_distribution<std::size_t> pos(xsens::kHeaderSize, msg.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7);
  for (;;) {
    auto copy = msg;
    copy[pos(rng_)] ^= static_cast<std::uint8_t>(1u << bit(rng_));
    if (!has_inner_header(copy)) {
      msg = std::move(copy);
      break;
    }
  }
  counts_.bad_checksum += 1;
  counts_.resync_bytes_skipped += msg.size();
  if (!survivors_.empty()) lost(1);
  push(std::move(msg), s.sample_time_fine);
}

void FaultyStreamBuilder::truncated(const TestSample& s, std::size_t keep) {
  auto msg = encode(s);
  if (keep < xsens::kHeaderSize || keep >= msg.size()) throw std::logic_error("bad keep");
  msg.resize(keep);
  truncated_segments_.push_back(segments_.size());
  counts_.bad_checksum += 1;
  counts_.resync_bytes_skipped += keep;
  if (!survivors_.empty()) lost(1);
  push(std::move(msg), s.sample_time_fine);
}

void FaultyStreamBuilder::oversize_header(std::uint32_t stf) {
  counts_.oversize_length += 1;
  counts_.resync_bytes_skipped += 6;
  push({xsens::kPreamble, xsens::kBusIdMaster, xsens::kMidMtData2, 0xFF, 0x7F, 0xFF}, stf);
}

void FaultyStreamBuilder::cut_off(const TestSample& s, std::size_t keep) {
  auto msg = encode(s);
  if (keep == 0 || keep >= msg.size()) throw std::logic_error("bad keep");
  msg.resize(keep);
  counts_.pending_at_end = keep;
  push(std::move(msg), s.sample_time_fine);
  cut_ = true;
}

std::vector<std::uint8_t> FaultyStreamBuilder::bytes() const {
  std::vector<std::uint8_t> all;
  all.reserve(size_);
  for (const Segment& s : segments_) all.insert(all.end(), s.bytes.begin(), s.bytes.end());
  return all;
}

ExpectedCounts FaultyStreamBuilder::finish() {
  // A truncated message's length field makes the parser read past its end into what follows; if
  // that span happens to sum to a valid checksum (1 in 256) the fragment's last byte is changed.
  for (int pass = 0;; ++pass) {
    if (pass > 10) throw std::logic_error("cannot break accidental checksums");
    const auto all = bytes();
    bool changed = false;
    for (std::size_t seg : truncated_segments_) {
      std::size_t start = 0;
      for (std::size_t k = 0; k < seg; ++k) start += segments_[k].bytes.size();
      const std::size_t total = xsens::kHeaderSize + all[start + 3] + 1;
      if (start + total > all.size()) throw std::logic_error("truncated message too near the end");
      std::uint8_t sum = 0;
      for (std::size_t i = start + 1; i < start + total; ++i) {
        sum = static_cast<std::uint8_t>(sum + all[i]);
      }
      if (sum != 0) continue;
      auto& frag = segments_[seg].bytes;
      if (frag.size() <= xsens::kHeaderSize) throw std::logic_error("fragment too short to fix");
      std::uint8_t& last = frag.back();
      do {
        last = static_cast<std::uint8_t>(last + 1);
      } while (last == xsens::kPreamble || last == xsens::kBusIdMaster);
      changed = true;
    }
    if (!changed) break;
  }
  const auto all = bytes();
  // Every header-looking byte pair must be one of ours.
  std::vector<bool> is_start(all.size() + 1, false);
  std::size_t at = 0;
  for (const Segment& s : segments_) {
    is_start[at] = true;
    at += s.bytes.size();
  }
  for (std::size_t i = 0; i + 1 < all.size(); ++i) {
    if (all[i] == xsens::kPreamble && all[i + 1] == xsens::kBusIdMaster && !is_start[i]) {
      throw std::logic_error("accidental header at byte " + std::to_string(i));
    }
  }
  return counts_;
}

}  // namespace vigs::drivers::test
