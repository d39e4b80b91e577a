// ONI file layout (OpenNI 2 "NI10" recording, file format version 1.0.1.0, 64-bit offsets), as
// OpenNI2's OniFile player reads it (Source/Drivers/OniFile: DataRecords, PlayerNode,
// PlayerDevice, PlayerStream). All integers little-endian, structures packed:
//   RecordingHeader  "NI10", version {1,0,1,0}, uint64 max timestamp (us), uint32 max node id
//   Record header    uint32 magic "NIR\0", type, node id, fields size (header + fields),
//                    payload size, uint64 undo position  (28 bytes)
// Per stream (node): NodeAdded {name, node type, codec "NONE", frames, min/max ts, seek table 0},
// its properties (map output mode, pixel format, cropping -- without a cropping property
// PlayerStream drops every frame --, field of view, required frame size) and NodeStateReady.
// Then NodeDataBegin per stream, the NewData records {ts, frame number 1..N, raw payload} in
// time order, and End. No seek table: clips are played front to back.
#include "io/oni/oni_clip_writer.hpp"

#include <cstring>
#include <memory>
#include <string_view>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/byte_buffer.hpp"
#include "io/io_error.hpp"

namespace vigs::io::oni {
namespace {

enum RecordType : std::uint32_t {
  kIntProperty = 0x03,
  kRealProperty = 0x04,
  kGeneralProperty = 0x06,
  kNodeDataBegin = 0x08,
  kNodeStateReady = 0x09,
  kNewData = 0x0A,
  kEnd = 0x0B,
  kNodeAdded = 0x0D,
};
constexpr std::uint32_t kRecordMagic = 0x0052494E;  // "NIR\0"
constexpr std::int32_t kNodeTypeDepth = 2;
constexpr std::int32_t kNodeTypeImage = 3;
constexpr std::uint32_t kCodecUncompressed =
    'N' | ('O' << 8) | ('N' << 16) | (std::uint32_t{'E'} << 24);
constexpr std::uint64_t kOniPixelFormatDepth1mm = 100;  // ONI_PIXEL_FORMAT_DEPTH_1_MM
constexpr std::uint64_t kOniPixelFormatRgb888 = 200;    // ONI_PIXEL_FORMAT_RGB888

// Builds one record: header, then fields; payload appended separately.
class RecordBuilder {
 public:
  RecordBuilder(std::vector<std::uint8_t>& out, std::uint32_t type, std::uint32_t node)
      : out_(out), w_(out), start_(out.size()) {
    w_.put(kRecordMagic);
    w_.put(type);
    w_.put(node);
    fields_at_ = w_.reserve<std::uint32_t>();
    payload_at_ = w_.reserve<std::uint32_t>();
    w_.put<std::uint64_t>(0);  // undo position: not used for front-to-back playback
  }
  ByteWriter& fields() { return w_; }
  void string(std::string_view s) {  // uint32 length including NUL, chars, NUL
    w_.put(static_cast<std::uint32_t>(s.size() + 1));
    w_.put_bytes(s);
    w_.put<std::uint8_t>(0);
  }
  void finish(std::span<const std::uint8_t> payload = {}) {
    w_.patch<std::uint32_t>(fields_at_, static_cast<std::uint32_t>(out_.size() - start_));
    w_.patch<std::uint32_t>(payload_at_, static_cast<std::uint32_t>(payload.size()));
    w_.put_bytes(payload);
  }

 private:
  std::vector<std::uint8_t>& out_;
  ByteWriter w_;
  std::size_t start_, fields_at_ = 0, payload_at_ = 0;
};

void int_prop(std::vector<std::uint8_t>& out, std::uint32_t node, std::string_view name,
              std::uint64_t value) {
  RecordBuilder r(out, kIntProperty, node);
  r.string(name);
  r.fields().put<std::uint32_t>(8);
  r.fields().put(value);
  r.finish();
}

void general_prop(std::vector<std::uint8_t>& out, std::uint32_t node, std::string_view name,
                  std::span<const std::uint8_t> data) {
  RecordBuilder r(out, kGeneralProperty, node);
  r.string(name);
  r.fields().put(static_cast<std::uint32_t>(data.size()));
  r.fields().put_bytes(data);
  r.finish();
}

}  // namespace

struct OniClipWriter::Impl {
  std::string path;
  OniClipSettings settings;
  std::unique_ptr<AtomicFile> file;  // opened at the first frame
  std::uint32_t frames = 0;
  std::uint64_t first_t_us = 0, last_t_us = 0;
  std::size_t header_bytes = 0;
  std::vector<std::uint8_t> record;  // one record at a time, reused
  bool closed = false;

  void add_node(std::vector<std::uint8_t>& out, std::uint32_t node, std::string_view name,
                std::int32_t type, std::uint64_t oni_format, std::uint32_t bytes_per_pixel) const {
    {
      RecordBuilder r(out, kNodeAdded, node);
      r.string(name);
      r.fields().put(type);
      r.fields().put(kCodecUncompressed);
      r.fields().put(frames);
      r.fields().put(first_t_us);
      r.fields().put(last_t_us);
      r.fields().put<std::uint64_t>(0);  // no seek table
      r.finish();
    }
    std::vector<std::uint8_t> b;
    ByteWriter w(b);
    w.put(settings.width);  // XnMapOutputMode {x res, y res, fps}
    w.put(settings.height);
    w.put(settings.fps);
    general_prop(out, node, "xnMapOutputMode", b);
    int_prop(out, node, "oniPixelFormat", oni_format);
    b.clear();
    w.put<std::int32_t>(0);  // XnCropping {XnBool enabled, uint16 x, y, width, height}: off
    for (int k = 0; k < 4; ++k) w.put<std::uint16_t>(0);
    general_prop(out, node, "xnCropping", b);
    b.clear();
    w.put(settings.hfov_rad);  // XnFieldOfView {double h, v}
    w.put(settings.vfov_rad);
    general_prop(out, node, "xnFOV", b);
    int_prop(out, node, "oniRequiredFrameSize",
             std::uint64_t{settings.width} * settings.height * bytes_per_pixel);
    int_prop(out, node, "xnIsGenerating", 1);
    RecordBuilder(out, kNodeStateReady, node).finish();
  }

  // Everything before the first frame record, for the frames added so far. Its size does not
  // depend on the counts and times (fixed-width fields), so close() rewrites it in place.
  std::vector<std::uint8_t> header() const {
    std::vector<std::uint8_t> out;
    ByteWriter w(out);
    w.put_bytes(std::string_view("NI10"));
    w.put<std::uint8_t>(1);  // version 1.0.1.0: 64-bit file offsets
    w.put<std::uint8_t>(0);
    w.put<std::uint16_t>(1);
    w.put<std::uint32_t>(0);
    w.put(last_t_us);         // global max timestamp
    w.put<std::uint32_t>(1);  // max node id (nodes 0 and 1)

    add_node(out, 0, "Depth", kNodeTypeDepth, kOniPixelFormatDepth1mm, 2);
    add_node(out, 1, "Image", kNodeTypeImage, kOniPixelFormatRgb888, 3);
    for (std::uint32_t node = 0; node < 2; ++node) {
      RecordBuilder r(out, kNodeDataBegin, node);
      r.fields().put(frames);  // SeekInfo {uint32 frames, uint64 max timestamp}, packed
      r.fields().put(last_t_us);
      r.finish();
    }
    return out;
  }

  void put(std::span<const std::uint8_t> bytes) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), file->file()) != bytes.size()) {
      throw IoError("ONI clip " + path + ": short write");
    }
  }

  // Frame `frames`' record for `node` (0 depth, 1 colour), through the reused buffer.
  void write_record(std::uint64_t t_us, std::uint32_t node, std::span<const std::uint8_t> payload) {
    record.clear();
    RecordBuilder r(record, kNewData, node);
    r.fields().put(t_us);
    r.fields().put(frames + 1);  // frame numbers start at 1
    r.finish(payload);
    put(record);
  }
};

OniClipWriter::OniClipWriter(std::string path, OniClipSettings settings)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = std::move(path);
  impl_->settings = settings;
  if (settings.width == 0 || settings.height == 0 || settings.fps == 0 ||
      std::uint64_t{settings.width} * settings.height * 3 > 1600u * 1200u * 3u) {
    throw IoError("ONI clip " + impl_->path +
                  ": width, height and fps must be > 0 and a frame at most 1600x1200");
  }
}

OniClipWriter::~OniClipWriter() = default;

void OniClipWriter::add_frame(std::span<const std::uint16_t> depth_mm,
                              std::span<const std::uint8_t> rgb) {
  add_frame_at(uniform_timestamp_us(impl_->frames, impl_->settings.fps), depth_mm, rgb);
}

void OniClipWriter::add_frame_at(std::uint64_t t_us, std::span<const std::uint16_t> depth_mm,
                                 std::span<const std::uint8_t> rgb) {
  Impl& m = *impl_;
  if (m.closed) throw IoError("ONI clip " + m.path + ": add_frame after close");
  if (t_us == 0 || (m.frames > 0 && t_us <= m.last_t_us)) {
    throw IoError("ONI clip " + m.path + ": frame " + std::to_string(m.frames) + " timestamp " +
                  std::to_string(t_us) + " us is not after the previous one (or is 0)");
  }
  const std::size_t n = std::size_t{m.settings.width} * m.settings.height;
  if (depth_mm.size() != n || rgb.size() != 3 * n) {
    throw IoError("ONI clip " + m.path + ": frame " + std::to_string(m.frames) + " has " +
                  std::to_string(depth_mm.size()) + " depth values and " +
                  std::to_string(rgb.size()) + " colour bytes, expected " + std::to_string(n) +
                  " and " + std::to_string(3 * n));
  }
  try {
    if (!m.file) {
      m.file = std::make_unique<AtomicFile>(m.path);
      m.first_t_us = m.last_t_us = t_us;
      const std::vector<std::uint8_t> h = m.header();
      m.header_bytes = h.size();
      m.put(h);
    }
    m.write_record(t_us, 0,
                   {reinterpret_cast<const std::uint8_t*>(depth_mm.data()), depth_mm.size_bytes()});
    m.write_record(t_us, 1, rgb);
  } catch (const IoError&) {
    m.file.reset();  // removes the temporary file
    throw;
  } catch (const std::exception& e) {
    m.file.reset();
    throw IoError("ONI clip " + m.path + ": " + e.what());
  }
  m.last_t_us = t_us;
  ++m.frames;
}

void OniClipWriter::close() {
  Impl& m = *impl_;
  if (m.closed) return;
  if (m.frames == 0 || !m.file) throw IoError("ONI clip " + m.path + ": no frames added");
  try {
    m.record.clear();
    RecordBuilder(m.record, kEnd, 0).finish();
    m.put(m.record);
    // The counts and the last time are known now: the header again, same size, in place.
    const std::vector<std::uint8_t> h = m.header();
    if (h.size() != m.header_bytes || std::fseek(m.file->file(), 0, SEEK_SET) != 0) {
      throw IoError("ONI clip " + m.path + ": cannot rewrite the header");
    }
    m.put(h);
    m.file->commit();
  } catch (const std::exception& e) {
    m.file.reset();
    throw IoError("ONI clip " + m.path + ": " + e.what());
  }
  m.file.reset();
  m.closed = true;
}

}  // namespace vigs::io::oni
