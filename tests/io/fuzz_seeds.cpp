// Seed corpus of the protocol fuzzer: valid frame streams (state and control frames,
// consecutive and with gaps) written one file each into the directory given.
#include <cstdio>
#include <string>
#include <vector>

#include "tmpc/io/protocol.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const std::string dir = argv[1];
  std::vector<std::uint8_t> frame;
  for (int k = 0; k < 8; ++k) {
    std::vector<std::uint8_t> stream;
    for (int j = 0; j < 3; ++j) {
      tmpc::io::StateFrame s;
      s.seq = static_cast<std::uint32_t>(1 + j * (k + 1));
      s.time = 0.012 * j + k;
      for (int i = 0; i < 20; ++i) s.x[static_cast<std::size_t>(i)] = 0.1 * (i - 10) * (k + 1);
      tmpc::io::encode(s, frame);
      stream.insert(stream.end(), frame.begin(), frame.end());
      tmpc::io::ControlFrame c;
      c.seq = s.seq;
      c.u = {10.0 + k, 10.5, -0.1 * j, 0.2};
      c.flags = static_cast<std::uint8_t>(k & 7);
      tmpc::io::encode(c, frame);
      stream.insert(stream.end(), frame.begin(), frame.end());
    }
    const std::string path = dir + "/seed" + std::to_string(k);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) return 1;
    std::fwrite(stream.data(), 1, stream.size(), f);
    std::fclose(f);
  }
  return 0;
}
