// XsensMtParser and encoder: exact decoding, chunking independence, resynchronisation and one
// counter per fault kind.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "drivers/serial_imu/byte_order.hpp"
#include "drivers/serial_imu/parser_factory.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"
#include "drivers/serial_imu/xsens_parser.hpp"
#include "xsens_test_stream.hpp"

namespace vigs::drivers {
namespace {

using test::TestSample;

struct Collect final : ImuSampleSink {
  std::vector<DeviceImuSample> samples;
  void on_sample(const DeviceImuSample& s) noexcept override { samples.push_back(s); }
};

void expect_same(const DeviceImuSample& got, const TestSample& want) {
  EXPECT_EQ(got.device_ticks, want.sample_time_fine);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(got.accel_mps2[i], want.accel_mps2[i]);
    EXPECT_EQ(got.gyro_rps[i], want.gyro_rps[i]);
  }
}

// Feeds `bytes` in chunks whose sizes come from `chunk` (0 means all at once).
std::vector<DeviceImuSample> parse(XsensMtParser& p, const std::vector<std::uint8_t>& bytes,
                                   std::size_t max_chunk, std::uint32_t seed = 1) {
  Collect sink;
  if (max_chunk == 0) {
    p.feed(bytes.data(), bytes.size(), sink);
    return sink.samples;
  }
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> len(1, max_chunk);
  for (std::size_t at = 0; at < bytes.size();) {
    const std::size_t n = std::min(len(rng), bytes.size() - at);
    p.feed(bytes.data() + at, n, sink);
    at += n;
  }
  return sink.samples;
}

TEST(XsensEncoder, MessageLayoutAndChecksum) {
  const auto msg = xsens::encode_mtdata2(0x01020304, {1.0, 2.0, 3.0}, {-1.0, 0.5, 0.25});
  ASSERT_EQ(msg.size(), 4u + 3 * 3 + 4 + 2 * 12 + 1);
  EXPECT_EQ(msg[0], 0xFA);
  EXPECT_EQ(msg[1], 0xFF);
  EXPECT_EQ(msg[2], 0x36);
  EXPECT_EQ(msg[3], msg.size() - 5);
  EXPECT_EQ(load_be_u16(&msg[4]), 0x1060);
  EXPECT_EQ(msg[6], 4);
  EXPECT_EQ(load_be_u32(&msg[7]), 0x01020304u);
  EXPECT_EQ(load_be_u16(&msg[11]), 0x4020);
  EXPECT_EQ(load_be_f32(&msg[14]), 1.0f);
  std::uint8_t sum = 0;
  for (std::size_t i = 1; i < msg.size(); ++i) sum = static_cast<std::uint8_t>(sum + msg[i]);
  EXPECT_EQ(sum, 0);
}

TEST(XsensParser, DecodesEveryPrecisionExactly) {
  const std::array<double, 3> a{9.80665, -0.125, 3.5}, g{0.001, -2.0, 0.75};
  for (auto prec :
       {xsens::Precision::kFloat32, xsens::Precision::kFixed1220, xsens::Precision::kFloat64}) {
    XsensMtParser p;
    const auto out = parse(p, xsens::encode_mtdata2(77, a, g, prec), 0);
    ASSERT_EQ(out.size(), 1u);
    for (int i = 0; i < 3; ++i) {
      const double tol = prec == xsens::Precision::kFloat64   ? 0.0
                         : prec == xsens::Precision::kFloat32 ? 1e-6 * std::abs(a[i])
                                                              : 1.0 / 1048576.0;
      EXPECT_NEAR(out[0].accel_mps2[i], a[i], tol);
      EXPECT_NEAR(out[0].gyro_rps[i], g[i], prec == xsens::Precision::kFloat32 ? 1e-6 : tol);
    }
    EXPECT_EQ(p.counters().packets_ok.get(), 1u);
  }
}

TEST(XsensParser, ByteByByteEqualsChunkedEqualsWhole) {
  const auto samples = test::euroc_samples(300, 1000);
  std::vector<std::uint8_t> bytes;
  for (const auto& s : samples) {
    const auto m = test::encode(s);
    bytes.insert(bytes.end(), m.begin(), m.end());
  }
  for (std::size_t chunk : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{64}}) {
    XsensMtParser p;
    const auto out = parse(p, bytes, chunk);
    ASSERT_EQ(out.size(), samples.size()) << "chunk " << chunk;
    for (std::size_t i = 0; i < out.size(); ++i) expect_same(out[i], samples[i]);
    EXPECT_EQ(p.counters().resync_bytes_skipped.get(), 0u);
    EXPECT_EQ(p.counters().bytes_in_messages.get(), bytes.size());
    EXPECT_EQ(p.pending_bytes(), 0u);
  }
}

TEST(XsensParser, ExtendedLengthAndUnknownDataIdsAreSkipped) {
  std::vector<std::uint8_t> payload;
  const std::vector<std::uint8_t> blob(200, 0x5A);
  xsens::append_packet(payload, 0x2010, blob);  // quaternion-group id of the wrong size: skipped
  xsens::append_packet(payload, 0xE020, blob);  // status group: skipped
  std::uint8_t stf[4];
  store_be_u32(stf, 0xFFFFFFF0u);
  xsens::append_packet(payload, xsens::kIdSampleTimeFine, stf);
  xsens::append_vec3(payload, xsens::kIdAcceleration | 0x4, {1, 2, 3}, xsens::Precision::kFloat64);
  xsens::append_vec3(payload, xsens::kIdRateOfTurn | 0x8, {4, 5, 6}, xsens::Precision::kFloat32);
  const auto msg = xsens::encode_message(xsens::kMidMtData2, payload);
  ASSERT_GT(payload.size(), 254u);
  ASSERT_EQ(msg[3], 0xFF);
  EXPECT_EQ(load_be_u16(&msg[4]), payload.size());
  for (std::size_t chunk : {std::size_t{0}, std::size_t{1}, std::size_t{5}}) {
    XsensMtParser p;
    const auto out = parse(p, msg, chunk);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].device_ticks, 0xFFFFFFF0u);
    EXPECT_EQ(out[0].accel_mps2[2], 3.0);
    EXPECT_EQ(out[0].gyro_rps[0], 4.0);
  }
}

TEST(XsensParser, OtherMessagesIncompleteAndMalformedPayloads) {
  XsensMtParser p;
  std::vector<std::uint8_t> bytes;
  auto add = [&](const std::vector<std::uint8_t>& m) {
    bytes.insert(bytes.end(), m.begin(), m.end());
  };
  add(xsens::encode_message(0x3E, {}));  // WakeUp: valid, not data
  std::vector<std::uint8_t> only_time;
  const std::uint8_t stf[4] = {0, 0, 0, 1};
  xsens::append_packet(only_time, xsens::kIdSampleTimeFine, stf);
  add(xsens::encode_message(xsens::kMidMtData2, only_time));  // no accel / gyro
  std::vector<std::uint8_t> overrun = only_time;
  overrun[2] = 9;  // field size beyond the payload
  add(xsens::encode_message(xsens::kMidMtData2, overrun));
  std::vector<std::uint8_t> fp1632 = only_time;
  const std::vector<std::uint8_t> eighteen(18, 0);
  xsens::append_packet(fp1632, xsens::kIdAcceleration | 0x2, eighteen);
  add(xsens::encode_message(xsens::kMidMtData2, fp1632));
  add(xsens::encode_mtdata2(2, {0, 0, 9.81}, {0, 0, 0}));
  const auto out = parse(p, bytes, 3);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].device_ticks, 2u);
  const auto& c = p.counters();
  EXPECT_EQ(c.other_messages.get(), 1u);
  EXPECT_EQ(c.incomplete_sample.get(), 1u);
  EXPECT_EQ(c.malformed_payload.get(), 1u);
  EXPECT_EQ(c.unsupported_format.get(), 1u);
  EXPECT_EQ(c.packets_ok.get(), 1u);
  EXPECT_EQ(c.bad_checksum.get() + c.resync_bytes_skipped.get(), 0u);
}

TEST(XsensParser, NeverTrustsALengthAboveTheMaximum) {
  XsensMtParser p;
  const auto good = test::encode(test::euroc_samples(1, 5)[0]);
  std::vector<std::uint8_t> bytes = {0xFA, 0xFF, 0x36, 0xFF, 0x08, 0x01};  // 2049 bytes announced
  bytes.insert(bytes.end(), good.begin(), good.end());
  const auto out = parse(p, bytes, 1);
  EXPECT_EQ(out.size(), 1u);  // found at once, not after 2 kB of look-ahead
  EXPECT_EQ(p.counters().oversize_length.get(), 1u);
  EXPECT_EQ(p.counters().resync_bytes_skipped.get(), 6u);
}

class FaultyStream : public ::testing::TestWithParam<std::size_t> {};

TEST_P(FaultyStream, YieldsExactlyTheGoodPacketsAndCountsEveryFault) {
  const auto samples = test::euroc_samples(400, 0xFFFFFFFFu - 50 * 200);  // wraps mid-stream
  test::FaultyStreamBuilder b(42);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> kind(0, 9);
  for (std::size_t i = 0; i + 2 < samples.size(); ++i) {
    switch (kind(rng)) {
      case 0:
        b.garbage(1 + i % 37, samples[i].sample_time_fine);
        b.good(samples[i]);
        break;
      case 1:
        b.flipped(samples[i]);
        break;
      case 2:
        b.truncated(samples[i], 4 + i % 30);
        break;
      case 3:
        b.oversize_header(samples[i].sample_time_fine);
        b.good(samples[i]);
        break;
      default:
        b.good(samples[i]);
    }
  }
  b.good(samples[samples.size() - 2]);
  b.cut_off(samples.back(), 20);
  const auto want = b.finish();
  ASSERT_GT(want.bad_checksum, 20u);
  ASSERT_GT(want.oversize_length, 5u);

  XsensMtParser p;
  const auto bytes = b.bytes();
  const auto out = parse(p, bytes, GetParam(), 3);
  ASSERT_EQ(out.size(), b.survivors().size());
  for (std::size_t i = 0; i < out.size(); ++i) expect_same(out[i], b.survivors()[i]);
  const auto& c = p.counters();
  EXPECT_EQ(c.packets_ok.get(), want.packets_ok);
  EXPECT_EQ(c.bad_checksum.get(), want.bad_checksum);
  EXPECT_EQ(c.oversize_length.get(), want.oversize_length);
  EXPECT_EQ(c.resync_bytes_skipped.get(), want.resync_bytes_skipped);
  EXPECT_EQ(c.bytes_in_messages.get(), want.bytes_in_messages);
  EXPECT_EQ(p.pending_bytes(), want.pending_at_end);
  EXPECT_EQ(c.bytes_fed.get(),
            c.bytes_in_messages.get() + c.resync_bytes_skipped.get() + p.pending_bytes());
}

INSTANTIATE_TEST_SUITE_P(Chunks, FaultyStream, ::testing::Values(0, 1, 13, 500));

TEST(XsensParser, RandomBytesNeverCrashAndAccountForEveryByte) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<std::uint8_t> bytes(200000);
  for (auto& x : bytes) x = static_cast<std::uint8_t>(byte(rng));
  // Seed many plausible headers so the length paths are exercised too.
  for (std::size_t i = 0; i + 6 < bytes.size(); i += 97) {
    bytes[i] = 0xFA;
    bytes[i + 1] = 0xFF;
  }
  XsensMtParser p;
  (void)parse(p, bytes, 300, 5);
  const auto& c = p.counters();
  EXPECT_EQ(c.bytes_fed.get(), bytes.size());
  EXPECT_EQ(c.bytes_fed.get(),
            c.bytes_in_messages.get() + c.resync_bytes_skipped.get() + p.pending_bytes());
  EXPECT_GT(c.bad_checksum.get() + c.oversize_length.get(), 100u);
}

TEST(ParserFactory, KnowsXsensAndNamesUnknownProtocols) {
  EXPECT_EQ(make_imu_parser("xsens_mt")->protocol_name(), "xsens_mt");
  EXPECT_EQ(imu_protocol_names().size(), 1u);
  try {
    (void)make_imu_parser("vectornav");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'vectornav'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("xsens_mt"), std::string::npos);
  }
}

}  // namespace
}  // namespace vigs::drivers
