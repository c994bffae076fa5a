// libFuzzer target of the serial-protocol parser (built when clang is available; see
// tests/io/check_fuzz.cmake), structure-aware: besides the raw byte stream, the input
// read as packets [u8 length][length bytes] gets a valid CRC-32 appended and is COBS
// framed by the harness, so the fuzzer reaches the checks behind the checksum
// (version, type, count, session, sequence, values). Through both decoders nothing may
// crash (ASan, UBSan), and every accepted frame must have a nonzero session, finite
// values inside the bounds, and survive an encode-decode round trip unchanged.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tmpc/io/protocol.hpp"
#include "tmpc/model/checksum.hpp"

namespace {

void require(bool ok) {
  if (!ok) __builtin_trap();
}

tmpc::io::DecoderSettings state_settings() {
  tmpc::io::DecoderSettings s = tmpc::io::state_decoder_settings(20, 1e4);
  s.time_bound = 1e6;
  return s;
}

void check_state(const tmpc::io::StateFrame& f, const tmpc::io::DecoderSettings& s) {
  require(f.session != 0 && f.n == s.values);
  require(std::isfinite(f.time) && std::abs(f.time) <= s.time_bound);
  for (std::size_t i = 0; i < f.n; ++i) require(std::isfinite(f.x[i]) && std::abs(f.x[i]) <= s.bound[i]);
  std::vector<std::uint8_t> wire;
  tmpc::io::encode(f, wire);
  tmpc::io::Decoder d(s);
  bool got = false;
  for (std::uint8_t c : wire) got = d.push(c) || got;
  require(got && d.state().seq == f.seq && d.state().session == f.session && d.state().time == f.time &&
          d.state().x == f.x);
}

void check_control(const tmpc::io::ControlFrame& f, const tmpc::io::DecoderSettings& s) {
  require(f.session != 0 && f.n == s.values);
  for (std::size_t i = 0; i < f.n; ++i) require(std::isfinite(f.u[i]) && std::abs(f.u[i]) <= s.bound[i]);
  std::vector<std::uint8_t> wire;
  tmpc::io::encode(f, wire);
  tmpc::io::Decoder d(s);
  bool got = false;
  for (std::uint8_t c : wire) got = d.push(c) || got;
  require(got && d.control().seq == f.seq && d.control().u == f.u && d.control().flags == f.flags);
}

struct Pair {
  tmpc::io::DecoderSettings ss = state_settings(), cs = tmpc::io::control_decoder_settings(4);
  tmpc::io::Decoder state{ss}, control{cs};
  long delimiters = 0;
  void push(std::uint8_t b) {
    delimiters += b == 0;
    if (state.push(b)) check_state(state.state(), ss);
    if (control.push(b)) check_control(control.control(), cs);
  }
  void verdicts_bounded() const {
    // A frame ends at a delimiter: never more verdicts than delimiters.
    require(state.counts().accepted + state.counts().rejected_total() <= delimiters);
    require(control.counts().accepted + control.counts().rejected_total() <= delimiters);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {  // The raw stream.
    Pair p;
    for (std::size_t i = 0; i < size; ++i) p.push(data[i]);
    p.verdicts_bounded();
  }
  {  // Packets with a valid checksum, COBS framed by the harness.
    Pair p;
    std::vector<std::uint8_t> packet, framed;
    for (std::size_t i = 0; i < size;) {
      const std::size_t len = std::min<std::size_t>(data[i++], size - i);
      packet.assign(data + i, data + i + len);
      i += len;
      const std::uint32_t crc = tmpc::crc32(packet.data(), packet.size());
      for (int k = 0; k < 4; ++k) packet.push_back(static_cast<std::uint8_t>(crc >> (8 * k)));
      framed.resize(packet.size() + packet.size() / 254 + 2);
      framed.resize(tmpc::io::cobs_encode(packet.data(), packet.size(), framed.data()));
      framed.push_back(0);
      for (std::uint8_t b : framed) p.push(b);
    }
    p.verdicts_bounded();
  }
  // COBS alone: decoding never writes past the buffer it is given.
  std::uint8_t out[64];
  const long n = tmpc::io::cobs_decode(data, size, out, sizeof out);
  require(n <= static_cast<long>(sizeof out));
  return 0;
}
