// libFuzzer target of the controller-artifact loader (built when clang is available;
// see tests/synthesis/check_fuzz_artifact.cmake), structure-aware: the input is the
// payload (the records); the harness writes the header (magic, version, length) and
// the CRC-32 around it, so the fuzzer reaches the record parser and the semantic checks
// behind the checksum. Nothing may crash (ASan, UBSan) or escape but ArtifactError, and
// an accepted artifact must serialize back to the same bytes. At exit it prints how many
// inputs were accepted: the check fails on none (a seed the loader refuses, or one
// libFuzzer truncated to -max_len, fuzzes the header parser only).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

#include "tmpc/model/checksum.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace {

void require(bool ok) {
  if (!ok) __builtin_trap();
}

std::size_t accepted = 0;

void report_accepted() { std::fprintf(stderr, "fuzz_artifact: %zu inputs accepted\n", accepted); }

void put_le(std::vector<std::uint8_t>& b, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool registered = std::atexit(report_accepted) == 0;
  require(registered);
  std::vector<std::uint8_t> file = {'T', 'M', 'P', 'C', 'A', 'R', 'T', '\0'};
  put_le(file, tmpc::kArtifactVersion, 4);
  put_le(file, size, 8);
  file.insert(file.end(), data, data + size);
  put_le(file, tmpc::crc32(file.data(), file.size()), 4);
  tmpc::ControllerArtifact a;
  try {
    a = tmpc::deserialize_artifact(file, "fuzz.tmpc");
  } catch (const tmpc::ArtifactError&) {
    return 0;  // refused with a message: fine
  } catch (const std::exception&) {
    require(false);  // any other exception is a loader bug
  }
  require(tmpc::serialize_artifact(a) == file);
  ++accepted;
  return 0;
}
