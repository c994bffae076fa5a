// Serial protocol v2: round trips, every rejection reason, the session and sequence
// rules (a restart reconnects, no single frame locks the link out), and a
// deterministic fuzz of 100,000 mutated frames (no crash, counted rejections, no
// corrupt frame accepted).
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "tmpc/io/protocol.hpp"
#include "tmpc/model/checksum.hpp"

namespace tmpc::io {
namespace {

constexpr std::uint32_t kSession = 0x1234abcd;

StateFrame sample_state(std::uint32_t seq, std::uint32_t session = kSession) {
  StateFrame f;
  f.session = session;
  f.seq = seq;
  f.time = 0.012 * seq;
  f.n = 20;
  for (std::size_t i = 0; i < 20; ++i) f.x[i] = 0.1 * static_cast<double>(i) - 0.7 + 1e-3 * seq;
  return f;
}

std::vector<std::uint8_t> wire(const StateFrame& f) {
  std::vector<std::uint8_t> b;
  encode(f, b);
  return b;
}

int feed(Decoder& d, const std::vector<std::uint8_t>& bytes) {
  int n = 0;
  for (std::uint8_t b : bytes) n += d.push(b);
  return n;
}

Decoder state_decoder(double bound = 1e4) { return Decoder(state_decoder_settings(20, bound)); }

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

TEST(Protocol, EveryFrameTypeRoundTripsWithItsSizeAndSession) {
  Decoder ds = state_decoder();
  ASSERT_EQ(feed(ds, wire(sample_state(7))), 1);
  EXPECT_EQ(ds.state().seq, 7u);
  EXPECT_EQ(ds.state().session, kSession);
  EXPECT_EQ(ds.state().n, 20);
  EXPECT_EQ(ds.state().x, sample_state(7).x);
  EXPECT_EQ(ds.state().time, sample_state(7).time);
  EXPECT_TRUE(ds.new_session());
  ControlFrame c;
  c.session = 99;
  c.seq = 3;
  c.n = 4;
  c.u = {11.7, 11.8, 0.01, -0.02};
  c.flags = ControlFrame::kFallback | ControlFrame::kClipped;
  Decoder dc(control_decoder_settings(4));
  std::vector<std::uint8_t> buf;
  encode(c, buf);
  ASSERT_EQ(feed(dc, buf), 1);
  EXPECT_EQ(dc.control().u, c.u);
  EXPECT_EQ(dc.control().flags, c.flags);
  EXPECT_EQ(dc.control().session, 99u);
  // The header carries the size: a frame of 3 inputs is refused by a 4-input decoder.
  c.n = 3;
  c.seq = 4;
  encode(c, buf);
  EXPECT_EQ(feed(dc, buf), 0);
  EXPECT_EQ(dc.counts()[Reject::Framing], 1);
}

TEST(Protocol, BadFramesAreCountedByReasonAndDropped) {
  Decoder d = state_decoder();
  StateFrame f = sample_state(1);
  f.x[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(feed(d, wire(f)), 0);
  EXPECT_EQ(d.counts()[Reject::NonFinite], 1);
  f = sample_state(2);
  f.x[0] = 1e6;
  EXPECT_EQ(feed(d, wire(f)), 0);
  EXPECT_EQ(d.counts()[Reject::Bounds], 1);
  f = sample_state(2);
  f.time = 1e8;  // beyond the time bound
  EXPECT_EQ(feed(d, wire(f)), 0);
  EXPECT_EQ(d.counts()[Reject::Bounds], 2);
  std::vector<std::uint8_t> buf = wire(sample_state(3));
  buf[7] ^= 0x01;
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.counts()[Reject::Crc] + d.counts()[Reject::Framing], 1);
  ControlFrame c;
  c.session = kSession;
  c.n = 4;
  encode(c, buf);  // wrong type for this decoder
  EXPECT_EQ(feed(d, buf), 0);
  EXPECT_EQ(d.counts()[Reject::Framing], 1 + (d.counts()[Reject::Crc] == 0));
  f = sample_state(4, 0);  // session 0 is never valid
  EXPECT_EQ(feed(d, wire(f)), 0);
  EXPECT_EQ(d.counts()[Reject::Session], 1);
  // Sequence: 10 accepted, 10 again is a duplicate, 13 accepted with 2 lost.
  EXPECT_EQ(feed(d, wire(sample_state(10))), 1);
  EXPECT_EQ(feed(d, wire(sample_state(10))), 0);
  EXPECT_EQ(d.counts()[Reject::Sequence], 1);
  EXPECT_EQ(feed(d, wire(sample_state(13))), 1);
  EXPECT_EQ(d.counts().lost, 2);
  EXPECT_EQ(d.skipped(), 2);
  // A run of garbage without delimiter is an oversize frame; the decoder resyncs.
  std::vector<std::uint8_t> junk(2000, 0x55);
  junk.push_back(0);
  EXPECT_EQ(feed(d, junk), 0);
  EXPECT_EQ(d.counts()[Reject::Framing], 2 + (d.counts()[Reject::Crc] == 0));
  EXPECT_EQ(feed(d, wire(sample_state(14))), 1);
  // A frame of another protocol version (valid CRC) is refused by version.
  buf = wire(sample_state(15));
  std::vector<std::uint8_t> packet(600), stuffed(700);
  const long len = cobs_decode(buf.data(), buf.size() - 1, packet.data(), packet.size());
  ASSERT_GT(len, 4);
  packet[0] = 1;
  const std::uint32_t crc = tmpc::crc32(packet.data(), static_cast<std::size_t>(len) - 4);
  for (int i = 0; i < 4; ++i) packet[static_cast<std::size_t>(len) - 4 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(crc >> (8 * i));
  stuffed.resize(cobs_encode(packet.data(), static_cast<std::size_t>(len), stuffed.data()));
  stuffed.push_back(0);
  EXPECT_EQ(feed(d, stuffed), 0);
  EXPECT_EQ(d.counts()[Reject::Version], 1);
  // The summary names every reason that occurred.
  const std::string sum = summary(d.counts());
  for (const char* r : {"non_finite", "bounds", "session", "sequence", "version", "framing"}) {
    EXPECT_NE(sum.find(r), std::string::npos) << r << " not in: " << sum;
  }
}

TEST(Protocol, ASingleFrameFarAheadCannotLockTheLinkOut) {
  Decoder d = state_decoder();
  for (std::uint32_t k = 1; k <= 5; ++k) ASSERT_EQ(feed(d, wire(sample_state(k))), 1);
  // One valid frame with its sequence number advanced by 2^31 - 1: refused ...
  StateFrame rogue = sample_state(6);
  rogue.seq = 5 + 0x7fffffffu;
  EXPECT_EQ(feed(d, wire(rogue)), 0);
  EXPECT_EQ(d.counts()[Reject::Sequence], 1);
  // ... and the sender's next frames are accepted as before.
  for (std::uint32_t k = 6; k <= 10; ++k) EXPECT_EQ(feed(d, wire(sample_state(k))), 1) << k;
  EXPECT_EQ(d.counts().resyncs, 0);
}

TEST(Protocol, ASenderWhoseCounterJumpedIsFollowedAfterThreeConsecutiveFrames) {
  Decoder d = state_decoder();
  for (std::uint32_t k = 1; k <= 5; ++k) ASSERT_EQ(feed(d, wire(sample_state(k))), 1);
  // The counter restarts from 1 in the same session (a sender without sessions):
  EXPECT_EQ(feed(d, wire(sample_state(1))), 0);  // a duplicate on its own
  EXPECT_EQ(feed(d, wire(sample_state(2))), 0);
  EXPECT_EQ(feed(d, wire(sample_state(3))), 1);  // third consecutive frame: re-anchored
  EXPECT_TRUE(d.resynced());
  EXPECT_EQ(d.counts().resyncs, 1);
  EXPECT_EQ(feed(d, wire(sample_state(4))), 1);
  EXPECT_FALSE(d.resynced());
}

TEST(Protocol, ARestartedPeerIsAdoptedAtItsSecondFrameAndAStrayFrameNever) {
  Decoder d = state_decoder();
  for (std::uint32_t k = 1; k <= 100; ++k) ASSERT_EQ(feed(d, wire(sample_state(k))), 1);
  // A lone frame of another session (stray bytes of a dead process) changes nothing.
  EXPECT_EQ(feed(d, wire(sample_state(1, 777))), 0);
  EXPECT_EQ(d.counts()[Reject::Session], 1);
  EXPECT_EQ(feed(d, wire(sample_state(101))), 1);
  EXPECT_EQ(d.session(), kSession);
  // The restarted peer counts from 1 again in a new session: adopted at its second frame.
  EXPECT_EQ(feed(d, wire(sample_state(1, 0xbeef))), 0);
  EXPECT_EQ(feed(d, wire(sample_state(2, 0xbeef))), 1);
  EXPECT_TRUE(d.new_session());
  EXPECT_EQ(d.session(), 0xbeefu);
  EXPECT_EQ(d.counts().session_changes, 1);
  for (std::uint32_t k = 3; k <= 10; ++k) EXPECT_EQ(feed(d, wire(sample_state(k, 0xbeef))), 1);
  // The old session's frames are now strays.
  EXPECT_EQ(feed(d, wire(sample_state(102))), 0);
  // A live session keeps the link against frames of another sender interleaved with it.
  for (std::uint32_t k = 11; k <= 30; ++k) {
    EXPECT_EQ(feed(d, wire(sample_state(k, 0xbeef))), 1);
    EXPECT_EQ(feed(d, wire(sample_state(200 + k, 4242))), 0);
  }
  EXPECT_EQ(d.session(), 0xbeefu);
}

TEST(Protocol, SessionIdsAreDrawnFreshAndNeverZero) {
  const std::uint32_t a = draw_session_id(), b = draw_session_id();
  EXPECT_NE(a, 0u);
  EXPECT_NE(b, 0u);
  EXPECT_NE(a, b);  // 2^-32 chance of a false failure
}

TEST(Protocol, BadSettingsAreRefused) {
  DecoderSettings s = state_decoder_settings(20);
  s.resync_frames = 1;  // one frame would re-anchor the link
  EXPECT_THROW(Decoder{s}, std::invalid_argument);
  EXPECT_THROW(Decoder{state_decoder_settings(kMaxStateValues + 1)}, std::invalid_argument);
}

TEST(Protocol, HundredThousandMutatedFramesNeverCrashOrPassCorrupt) {
  std::mt19937_64 rng(2024);
  Decoder d = state_decoder();
  long accepted_corrupt = 0, mutated = 0;
  for (std::uint32_t k = 1; k <= 100000; ++k) {
    const StateFrame f = sample_state(k);
    std::vector<std::uint8_t> buf = wire(f);
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
    const long before = d.counts().accepted;
    feed(d, buf);
    if (d.counts().accepted > before && kind != 0) {
      // Accepted after a mutation: only legitimate if the bytes still decode to f.
      if (d.state().x != f.x || d.state().seq != f.seq || d.state().time != f.time) ++accepted_corrupt;
    }
  }
  EXPECT_EQ(accepted_corrupt, 0);
  EXPECT_GE(d.counts().rejected_total(), mutated * 9 / 10);
  EXPECT_GT(d.counts().accepted, 19000);
}

}  // namespace
}  // namespace tmpc::io
