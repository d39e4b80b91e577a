#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace vigs::io {

/// Appends little-endian fixed-width values and length-prefixed fields to a byte vector
/// (MCAP records, ROS 1 messages). The host must be little-endian (checked at compile time).
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}

  template <class T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    static_assert(std::endian::native == std::endian::little, "little-endian host required");
    const std::size_t at = out_.size();
    out_.resize(at + sizeof(T));
    std::memcpy(out_.data() + at, &value, sizeof(T));
  }
  void put_bytes(std::span<const std::uint8_t> bytes) { append(bytes.data(), bytes.size()); }
  void put_bytes(std::string_view text) { append(text.data(), text.size()); }
  /// uint32 length, then the bytes (MCAP String, ROS 1 string).
  void put_string(std::string_view text) {
    put(static_cast<std::uint32_t>(text.size()));
    put_bytes(text);
  }
  /// Writes a placeholder and returns its position, for lengths known only later.
  template <class T>
  std::size_t reserve() {
    const std::size_t at = out_.size();
    put(T{});
    return at;
  }
  template <class T>
  void patch(std::size_t at, T value) {
    std::memcpy(out_.data() + at, &value, sizeof(T));
  }
  std::size_t size() const { return out_.size(); }

 private:
  void append(const void* p, std::size_t n) {
    if (n == 0) return;
    const std::size_t at = out_.size();
    out_.resize(at + n);
    std::memcpy(out_.data() + at, p, n);
  }
  std::vector<std::uint8_t>& out_;
};

/// Bounds-checked little-endian reader over a byte span. Every get reports failure instead of
/// reading past the end, so malformed input cannot crash the caller.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  template <class T>
  [[nodiscard]] bool get(T& value) {
    static_assert(std::is_arithmetic_v<T>);
    if (remaining() < sizeof(T)) return false;
    std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  [[nodiscard]] bool get_span(std::size_t n, std::span<const std::uint8_t>& out) {
    if (remaining() < n) return false;
    out = bytes_.subspan(pos_, n);
    pos_ += n;
    return true;
  }
  /// uint32 length-prefixed string.
  [[nodiscard]] bool get_string(std::string& out) {
    std::uint32_t n = 0;
    std::span<const std::uint8_t> s;
    if (!get(n) || !get_span(n, s)) return false;
    out.assign(reinterpret_cast<const char*>(s.data()), s.size());
    return true;
  }
  [[nodiscard]] bool skip(std::size_t n) {
    if (remaining() < n) return false;
    pos_ += n;
    return true;
  }
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::span<const std::uint8_t> rest() const { return bytes_.subspan(pos_); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
};

}  // namespace vigs::io
