// Seed corpus of the protocol fuzzer, written one file each into the directory given:
// valid frame streams (state and control frames, consecutive, with gaps, a session
// change), and the same frames as the structure-aware form [u8 length][packet without
// its CRC] that the harness frames itself.
#include <cstdio>
#include <string>
#include <vector>

#include "tmpc/io/protocol.hpp"

namespace {

bool write(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  return true;
}

/// The packet inside a wire frame (COBS decoded, CRC dropped), behind its length byte.
void append_structured(const std::vector<std::uint8_t>& frame, std::vector<std::uint8_t>& out) {
  std::vector<std::uint8_t> packet(frame.size());
  const long n = tmpc::io::cobs_decode(frame.data(), frame.size() - 1, packet.data(), packet.size());
  if (n < 4 || n - 4 > 255) return;
  out.push_back(static_cast<std::uint8_t>(n - 4));
  out.insert(out.end(), packet.begin(), packet.begin() + (n - 4));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const std::string dir = argv[1];
  std::vector<std::uint8_t> frame;
  for (int k = 0; k < 8; ++k) {
    std::vector<std::uint8_t> stream, structured;
    for (int j = 0; j < 3; ++j) {
      tmpc::io::StateFrame s;
      s.session = k < 4 ? 0x1000u + static_cast<unsigned>(j / 2) : 0xabcdu;
      s.seq = static_cast<std::uint32_t>(1 + j * (k + 1));
      s.time = 0.012 * j + k;
      s.n = 20;
      for (int i = 0; i < 20; ++i) s.x[static_cast<std::size_t>(i)] = 0.1 * (i - 10) * (k + 1);
      tmpc::io::encode(s, frame);
      stream.insert(stream.end(), frame.begin(), frame.end());
      append_structured(frame, structured);
      tmpc::io::ControlFrame c;
      c.session = 0x2000u + static_cast<unsigned>(k);
      c.seq = s.seq;
      c.n = 4;
      c.u = {10.0 + k, 10.5, -0.1 * j, 0.2};
      c.flags = static_cast<std::uint8_t>(k & 7);
      tmpc::io::encode(c, frame);
      stream.insert(stream.end(), frame.begin(), frame.end());
      append_structured(frame, structured);
    }
    if (!write(dir + "/seed" + std::to_string(k), stream)) return 1;
    if (!write(dir + "/structured" + std::to_string(k), structured)) return 1;
  }
  return 0;
}
