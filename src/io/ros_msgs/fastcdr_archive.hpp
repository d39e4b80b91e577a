#pragma once
// Internal: CDR (XCDR1, little-endian, ROS 2 "cdr" message encoding) archives on eProsima
// Fast CDR (Debian libfastcdr-dev), the CDR library Fast DDS uses, taking the same visit
// functions (visit_fields.hpp) as the codecs' own archives in archive.hpp.
//
// Not the production codec: issue #10 asked for Fast CDR in the MCAP codecs unless it measured
// slower than the own encoder, and in bench_io it does (Imu encode about 2.8x, decode 1.4x the
// CPU time; images equal within noise, see BENCHMARKS.md "CDR: own archive vs Fast CDR"), so
// archive.hpp stays. These archives keep the two honest instead: test_cdr_fastcdr checks that
// every message type is byte-identical and cross-decodes between them, i.e. recordings and
// DDS samples share one CDR format, and bench_io keeps the comparison measurable. Users link
// fastcdr themselves (vigs_io does not).
//
// What stays here rather than in Fast CDR, and why:
//  - Fast CDR writes into a caller-sized buffer; SizeBound gives an upper bound of the encoded
//    size from the same visit, so one exact-size buffer is filled in place, without reallocation.
//  - Decoding checks every sequence length against the bytes left before resizing (Fast CDR
//    would resize a std::vector to a corrupt length first) and that strings end in NUL (Fast CDR
//    accepts either), and turns Fast CDR's exceptions into DecodeError naming the message type,
//    field and byte offset; bools are read as a byte (any non-zero is true), as before.
//  - The 4-byte encapsulation header is checked to be CDR_LE before Fast CDR reads it (Fast CDR
//    would silently switch to big-endian).
#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs::detail {

/// Upper bound of a message's CDR size: each field's bytes plus its worst-case alignment.
class SizeBound {
 public:
  static constexpr bool kRos1 = false;
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const char*, const T&) { bytes += 2 * sizeof(T); }
  void operator()(const char*, const Time&) { bytes += 8 + 3; }
  void operator()(const char*, const std::string& s) { bytes += 4 + 3 + s.size() + 1; }
  template <class T>
  void operator()(const char*, const std::vector<T>& v) {
    bytes += 4 + 3 + v.size() * sizeof(T) + sizeof(T);
  }
  template <class T, std::size_t N>
  void operator()(const char*, const std::array<T, N>&) {
    bytes += N * sizeof(T) + sizeof(T);
  }
  std::size_t bytes = 4;  // encapsulation header
};

class FastCdrEncoder {
 public:
  static constexpr bool kRos1 = false;
  /// `out` must already hold at least SizeBound bytes; finish() trims it to the encoded size.
  explicit FastCdrEncoder(std::vector<std::uint8_t>& out)
      : out_(out),
        buffer_(reinterpret_cast<char*>(out.data()), out.size()),
        cdr_(buffer_, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS, eprosima::fastcdr::Cdr::DDS_CDR) {
    cdr_.serialize_encapsulation();
  }
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const char*, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      cdr_.serialize(static_cast<std::uint8_t>(v ? 1 : 0));
    } else {
      cdr_.serialize(v);
    }
  }
  void operator()(const char*, const Time& t) {
    cdr_.serialize(t.sec);
    cdr_.serialize(t.nanosec);
  }
  void operator()(const char*, const std::string& s) { cdr_.serialize(s); }
  template <class T>
  void operator()(const char*, const std::vector<T>& v) {
    cdr_.serialize(static_cast<std::uint32_t>(v.size()));
    if (!v.empty()) cdr_.serializeArray(v.data(), v.size());
  }
  template <class T, std::size_t N>
  void operator()(const char*, const std::array<T, N>& a) {
    cdr_.serializeArray(a.data(), N);
  }
  void finish() { out_.resize(cdr_.getSerializedDataLength()); }

 private:
  std::vector<std::uint8_t>& out_;
  eprosima::fastcdr::FastBuffer buffer_;
  eprosima::fastcdr::Cdr cdr_;
};

class FastCdrDecoder {
 public:
  static constexpr bool kRos1 = false;
  FastCdrDecoder(std::span<const std::uint8_t> bytes, std::string_view type)
      : size_(bytes.size()),
        type_(type),
        // Fast CDR only reads through this pointer; its buffer type is not const-qualified.
        buffer_(const_cast<char*>(reinterpret_cast<const char*>(bytes.data())), bytes.size()),
        cdr_(buffer_, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS, eprosima::fastcdr::Cdr::DDS_CDR) {
    if (bytes.size() < 4) fail("encapsulation header", "message shorter than 4 bytes");
    if (bytes[0] != 0x00 || bytes[1] != 0x01) {
      fail("encapsulation header", "not CDR little-endian (expected 00 01, got " +
                                       std::to_string(bytes[0]) + " " + std::to_string(bytes[1]) +
                                       ")");
    }
    guarded("encapsulation header", [&] { cdr_.read_encapsulation(); });
  }
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const char* name, T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      std::uint8_t b = 0;
      guarded(name, [&] { cdr_.deserialize(b); });
      v = b != 0;
    } else {
      guarded(name, [&] { cdr_.deserialize(v); });
    }
  }
  void operator()(const char* name, Time& t) {
    guarded(name, [&] {
      cdr_.deserialize(t.sec);
      cdr_.deserialize(t.nanosec);
    });
  }
  void operator()(const char* name, std::string& s) {
    std::uint32_t n = 0;
    guarded(name, [&] { cdr_.deserialize(n); });
    need(name, n);
    // Read as a char array (not Cdr::jump): Fast CDR 1.0 tracks the last datum's size to skip
    // alignment, and only its own reads update that.
    s.resize(n);
    if (n == 0) return;
    guarded(name, [&] { cdr_.deserializeArray(s.data(), n); });
    if (s.back() != '\0') fail(name, "CDR string without terminating NUL");
    s.pop_back();
  }
  template <class T>
  void operator()(const char* name, std::vector<T>& v) {
    std::uint32_t n = 0;
    guarded(name, [&] { cdr_.deserialize(n); });
    if (n > remaining() / sizeof(T))
      fail(name, "sequence of " + std::to_string(n) + " elements does not fit");
    v.resize(n);
    if (n > 0) guarded(name, [&] { cdr_.deserializeArray(v.data(), n); });
  }
  template <class T, std::size_t N>
  void operator()(const char* name, std::array<T, N>& a) {
    guarded(name, [&] { cdr_.deserializeArray(a.data(), N); });
  }
  /// Call after the last field: only CDR alignment padding may be left.
  void finish() {
    if (remaining() > 7u) {
      fail("end", std::to_string(remaining()) + " unexpected trailing bytes (wrong type?)");
    }
  }

 private:
  std::size_t pos() const { return cdr_.getSerializedDataLength(); }
  std::size_t remaining() const { return size_ - pos(); }
  [[noreturn]] void fail(const char* field, const std::string& what) const {
    throw DecodeError(std::string(type_) + " (cdr): field '" + field + "' at byte " +
                      std::to_string(pos()) + ": " + what);
  }
  void need(const char* name, std::size_t n) const {
    if (remaining() < n) {
      fail(name, "needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left");
    }
  }
  template <class F>
  void guarded(const char* name, F&& f) {
    try {
      f();
    } catch (const eprosima::fastcdr::exception::Exception& e) {
      fail(name, std::string("needs more bytes than the ") + std::to_string(remaining()) +
                     " left (" + e.what() + ")");
    }
  }
  std::size_t size_;
  std::string_view type_;
  eprosima::fastcdr::FastBuffer buffer_;
  eprosima::fastcdr::Cdr cdr_;
};

}  // namespace vigs::io::ros_msgs::detail
