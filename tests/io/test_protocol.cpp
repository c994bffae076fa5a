// Serial protocol: round trips, every rejection class, and a deterministic fuzz of
// 100,000 mutated frames (no crash, counted rejections, no corrupt frame accepted).
#include <random>

#include <gtest/gtest.h>

#include "tmpc/io/protocol.hpp"

namespace tmpc::io {
namespace {

StateFrame sample_state(std::uint32_t seq) {
  StateFrame f;
  f.seq = seq;
  f.time = 0.012 * seq;
  for (std::size_t i = 0; i < 20; ++i) f.x[i] = 0.1 * static_cast<double>(i) - 0.7 + 1e-3 * seq;
  return f;
}

int feed(Decoder& d, const std::vector<std::uint8_t>& bytes) {
  int n = 0;
  for (std::uint8_t b : bytes) n += d.push(b);
  return n;
}

TEST(Protocol, CobsRoundTripsArbitraryBytes) {
  std::mt19937 rng(1);
  for (int len : {0, 1, 2, 253, 254, 255, 256, 600}) {
    std::vector<std::uint8_t> in(static_cast<std::size_t>(len));
    for (auto& b : in) b = static_cast<std::uint8_t>(rng() % 4 == 0 ? 0 : rng());
    std::vector<std::uint8_t> enc(in.size() + in.size() / 254 + 2), dec(in.size() + 1);
    const std::size_t n = cobs_encode(in.data(), in.size(), enc.data());
    for (std::size_t i = 0; i < n; ++i) ASSERT_NE(enc[i], 0) << "zero byte inside a COBS frame";
    const long m = cobs_decode(enc.data(), n, dec.data(), dec.size());
    ASSERT_EQ(m, len);
    EXPECT_TRUE(std::equal(in.begin(), in.end(), dec.begin()));
  }
}

TEST(Protocol, EveryFrameTypeRoundTrips) {
  std::vector<std::uint8_t> buf;
  Decoder ds(FrameType::State);
  encode(sample_state(7), buf);
  ASSERT_EQ(feed(ds, buf), 1);
  EXPECT_EQ(ds.state().seq, 7u);
  EXPECT_EQ(ds.state().x, sample_state(7).x);
  EXPECT_EQ(ds.state().time, sample_state(7).time);
  ControlFrame c;
  c.seq = 3;
  c.u = {11.7, 11.8, 0.01, -0.02};
  c.flags = ControlFrame::kFallback | ControlFrame::kClipped;
  Decoder dc(FrameType::Control);
  encode(c, buf);
  ASSERT_EQ(feed(dc, buf), 1);
  EXPECT_EQ(dc.control().u, c.u);
  EXPECT_EQ(dc.control().flags, c.flags);
}

TEST(Protocol, BadFramesAreCountedByReasonAndDropped) {
  std::vector<std::uint8_t> buf;
  Decoder d(FrameType::State);
  StateFrame f = sample_state(1);
  f.x[3] = std::numeric_limits<double>::quiet_NaN();
  encode(f, buf);
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.stats().non_finite, 1);
  f = sample_state(2);
  f.x[0] = 1e6;
  encode(f, buf);
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.stats().out_of_bounds, 1);
  encode(sample_state(3), buf);
  buf[5] ^= 0x01;
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.stats().bad_crc + d.stats().bad_cobs, 1);
  ControlFrame c;
  encode(c, buf);  // wrong type for this decoder
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.stats().unknown_type, 1);
  // Sequence: 10 accepted, 10 again is stale, 13 accepted with a gap of 2.
  encode(sample_state(10), buf);
  EXPECT_EQ(feed(d, buf), 1);
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.stats().stale_sequence, 1);
  encode(sample_state(13), buf);
  EXPECT_EQ(feed(d, buf), 1);
  EXPECT_EQ(d.stats().sequence_gaps, 2);
  // A run of garbage without delimiter is an oversize frame; the decoder resyncs.
  std::vector<std::uint8_t> junk(1000, 0x55);
  junk.push_back(0);
  EXPECT_EQ(feed(d, junk), 0);
  EXPECT_EQ(d.stats().oversize, 1);
  encode(sample_state(14), buf);
  EXPECT_EQ(feed(d, buf), 1);
}

TEST(Protocol, HundredThousandMutatedFramesNeverCrashOrPassCorrupt) {
  std::mt19937_64 rng(2024);
  std::vector<std::uint8_t> buf;
  Decoder d(FrameType::State);
  long accepted_corrupt = 0, mutated = 0;
  for (std::uint32_t k = 1; k <= 100000; ++k) {
    const StateFrame f = sample_state(k);
    encode(f, buf);
    const int kind = static_cast<int>(rng() % 5);
    if (kind == 0) {
      // intact frame
    } else if (kind == 1) {
      buf[rng() % (buf.size() - 1)] ^= static_cast<std::uint8_t>(1 + rng() % 255);  // flip a byte
    } else if (kind == 2) {
      buf.erase(buf.begin() + static_cast<long>(rng() % (buf.size() - 1)));  // drop a byte
    } else if (kind == 3) {
      buf.insert(buf.begin() + static_cast<long>(rng() % (buf.size() - 1)), static_cast<std::uint8_t>(rng()));
    } else {
      buf.resize(rng() % buf.size());  // truncated, the next frame's delimiter ends it
      buf.push_back(0);
    }
    mutated += kind != 0;
    const long before = d.stats().accepted;
    feed(d, buf);
    if (d.stats().accepted > before && kind != 0) {
      // Accepted after a mutation: only legitimate if the bytes still decode to f.
      if (d.state().x != f.x || d.state().seq != f.seq || d.state().time != f.time) ++accepted_corrupt;
    }
  }
  EXPECT_EQ(accepted_corrupt, 0);
  EXPECT_GE(d.stats().rejected(), mutated * 9 / 10);
  EXPECT_GT(d.stats().accepted, 19000);
}

}  // namespace
}  // namespace tmpc::io
