#pragma once
// Internal: field-by-field archives shared by all message codecs. One visit function per message
// type drives all four (CDR / ROS 1, encode / decode), so the layouts cannot drift apart.
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs::detail {

/// Encoder. kRos1 = false: XCDR1 little-endian (alignment relative to the end of the 4-byte
/// encapsulation header, strings with NUL); true: ROS 1 (packed, strings without NUL).
template <bool Ros1>
class Encoder {
 public:
  static constexpr bool kRos1 = Ros1;
  explicit Encoder(std::vector<std::uint8_t>& out) : out_(out) {
    out_.clear();
    if (!Ros1) {
      static constexpr std::uint8_t kEncapsulation[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE
      raw(kEncapsulation, sizeof(kEncapsulation));
    }
  }
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const char*, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      put(static_cast<std::uint8_t>(v ? 1 : 0));
    } else {
      put(v);
    }
  }
  void operator()(const char*, const Time& t) {
    if (Ros1) {
      put(static_cast<std::uint32_t>(t.sec));
    } else {
      put(t.sec);
    }
    put(t.nanosec);
  }
  void operator()(const char*, const std::string& s) {
    put(static_cast<std::uint32_t>(s.size() + (Ros1 ? 0 : 1)));
    out_.insert(out_.end(), s.begin(), s.end());
    if (!Ros1) out_.push_back(0);
  }
  template <class T>
  void operator()(const char* name, const std::vector<T>& v) {
    put(static_cast<std::uint32_t>(v.size()));
    if (v.empty()) return;
    align(sizeof(T));
    raw(v.data(), v.size() * sizeof(T));
    (void)name;
  }
  template <class T, std::size_t N>
  void operator()(const char*, const std::array<T, N>& a) {
    align(sizeof(T));
    raw(a.data(), N * sizeof(T));
  }

 private:
  void align(std::size_t n) {
    if (Ros1) return;
    while ((out_.size() - 4) % n != 0) out_.push_back(0);
  }
  template <class T>
  void put(T v) {
    align(sizeof(T));
    raw(&v, sizeof(T));
  }
  void raw(const void* p, std::size_t n) {
    static_assert(std::endian::native == std::endian::little, "little-endian host required");
    const std::size_t at = out_.size();
    out_.resize(at + n);
    std::memcpy(out_.data() + at, p, n);
  }
  std::vector<std::uint8_t>& out_;
};

/// Decoder with the same rules; throws DecodeError naming type, field and byte offset.
template <bool Ros1>
class Decoder {
 public:
  static constexpr bool kRos1 = Ros1;
  Decoder(std::span<const std::uint8_t> bytes, std::string_view type) : in_(bytes), type_(type) {
    if (!Ros1) {
      if (in_.size() < 4) fail("encapsulation header", "message shorter than 4 bytes");
      if (in_[0] != 0x00 || in_[1] != 0x01) {
        fail("encapsulation header", "not CDR little-endian (expected 00 01, got " +
                                         std::to_string(in_[0]) + " " + std::to_string(in_[1]) +
                                         ")");
      }
      pos_ = 4;
    }
  }
  template <class T>
  requires std::is_arithmetic_v<T>
  void operator()(const char* name, T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      std::uint8_t b = 0;
      get(name, b);
      v = b != 0;
    } else {
      get(name, v);
    }
  }
  void operator()(const char* name, Time& t) {
    if (Ros1) {
      std::uint32_t s = 0;
      get(name, s);
      t.sec = static_cast<std::int32_t>(s);
    } else {
      get(name, t.sec);
    }
    get(name, t.nanosec);
  }
  void operator()(const char* name, std::string& s) {
    std::uint32_t n = 0;
    get(name, n);
    need(name, n);
    const char* p = reinterpret_cast<const char*>(in_.data() + pos_);
    if (!Ros1 && n > 0) {
      if (p[n - 1] != '\0') fail(name, "CDR string without terminating NUL");
      s.assign(p, n - 1);
    } else {
      s.assign(p, n);
    }
    pos_ += n;
  }
  template <class T>
  void operator()(const char* name, std::vector<T>& v) {
    std::uint32_t n = 0;
    get(name, n);
    if (n > 0) align(name, sizeof(T));
    if (n > remaining() / sizeof(T))
      fail(name, "sequence of " + std::to_string(n) + " elements does not fit");
    v.resize(n);
    take(name, v.data(), std::size_t{n} * sizeof(T));
  }
  template <class T, std::size_t N>
  void operator()(const char* name, std::array<T, N>& a) {
    align(name, sizeof(T));
    take(name, a.data(), N * sizeof(T));
  }
  /// A byte sequence viewed in place (no copy): valid while the decoded bytes are.
  void operator()(const char* name, std::span<const std::uint8_t>& v) {
    std::uint32_t n = 0;
    get(name, n);
    if (n > remaining()) fail(name, "sequence of " + std::to_string(n) + " elements does not fit");
    v = in_.subspan(pos_, n);
    pos_ += n;
  }
  /// Call after the last field: only CDR alignment padding may be left.
  void finish() {
    if (remaining() > (Ros1 ? 0u : 7u)) {
      fail("end", std::to_string(remaining()) + " unexpected trailing bytes (wrong type?)");
    }
  }

 private:
  std::size_t remaining() const { return in_.size() - pos_; }
  [[noreturn]] void fail(const char* field, const std::string& what) const {
    throw DecodeError(std::string(type_) + (Ros1 ? " (ros1)" : " (cdr)") + ": field '" + field +
                      "' at byte " + std::to_string(pos_) + ": " + what);
  }
  void need(const char* name, std::size_t n) const {
    if (remaining() < n) {
      fail(name, "needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left");
    }
  }
  void align(const char* name, std::size_t n) {
    if (Ros1) return;
    const std::size_t pad = (n - (pos_ - 4) % n) % n;
    need(name, pad);
    pos_ += pad;
  }
  template <class T>
  void get(const char* name, T& v) {
    align(name, sizeof(T));
    take(name, &v, sizeof(T));
  }
  void take(const char* name, void* p, std::size_t n) {
    need(name, n);
    if (n > 0) std::memcpy(p, in_.data() + pos_, n);
    pos_ += n;
  }
  std::span<const std::uint8_t> in_;
  std::string_view type_;
  std::size_t pos_ = 0;
};

template <class Ar, class H>
void visit_header(Ar& ar, H& h) {
  if constexpr (Ar::kRos1) ar("header.seq", h.seq);
  ar("header.stamp", h.stamp);
  ar("header.frame_id", h.frame_id);
}

/// Runs `visit(archive, msg)` with the right encoder.
template <class Msg, class Visit>
void encode_with(const Msg& msg, Encoding encoding, std::vector<std::uint8_t>& out, Visit visit) {
  if (encoding == Encoding::kRos1) {
    Encoder<true> ar(out);
    visit(ar, msg);
  } else {
    Encoder<false> ar(out);
    visit(ar, msg);
  }
}

template <class Msg, class Visit>
void decode_with(std::span<const std::uint8_t> bytes, Encoding encoding, Msg& msg, Visit visit) {
  if (encoding == Encoding::kRos1) {
    Decoder<true> ar(bytes, MessageTraits<Msg>::kRos1Name);
    visit(ar, msg);
    ar.finish();
  } else {
    Decoder<false> ar(bytes, MessageTraits<Msg>::kRos2Name);
    visit(ar, msg);
    ar.finish();
  }
}

/// Like decode_with but for the leading fields only: the bytes after them are not read or checked.
template <class Msg, class Visit>
void decode_prefix_with(std::span<const std::uint8_t> bytes, Encoding encoding, Msg& msg,
                        Visit visit) {
  if (encoding == Encoding::kRos1) {
    Decoder<true> ar(bytes, MessageTraits<Msg>::kRos1Name);
    visit(ar, msg);
  } else {
    Decoder<false> ar(bytes, MessageTraits<Msg>::kRos2Name);
    visit(ar, msg);
  }
}

}  // namespace vigs::io::ros_msgs::detail
