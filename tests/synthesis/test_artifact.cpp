// Controller artifact: bit-exact round trip, every corruption class rejected with
// its message, and a fuzz of single-byte mutations and truncations.
#include <random>

#include <gtest/gtest.h>

#include "design_fixture.hpp"

namespace tmpc {
namespace {

const std::vector<std::uint8_t>& bytes() {
  static const std::vector<std::uint8_t> b = serialize_artifact(make_artifact(test::quick_design()));
  return b;
}

std::string error_of(const std::vector<std::uint8_t>& b) {
  try {
    deserialize_artifact(b, "t.tmpc");
  } catch (const ArtifactError& e) {
    return e.what();
  }
  return "";
}

void fix_crc(std::vector<std::uint8_t>& b) {
  const std::uint32_t c = crc32(b.data(), b.size() - 4);
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(c >> (8 * i));
}

TEST(Artifact, RoundTripIsBitExact) {
  const ControllerArtifact a = deserialize_artifact(bytes(), "t.tmpc");
  EXPECT_EQ(serialize_artifact(a), bytes());
  const ControllerArtifact& ref = make_artifact(test::quick_design());
  EXPECT_EQ(a.K, ref.K);
  EXPECT_EQ(a.Z.G, ref.Z.G);
  EXPECT_EQ(a.config_text, ref.config_text);
  // The QP data rebuilt from the artifact equals the design's.
  EXPECT_EQ(a.qp().H, test::quick_design().qp.H);
}

TEST(Artifact, EveryCorruptionClassIsRejectedWithItsMessage) {
  std::vector<std::uint8_t> b = bytes();
  b[0] = 'X';
  EXPECT_NE(error_of(b).find("bad magic"), std::string::npos);
  b = bytes();
  b[8] = 7;
  fix_crc(b);
  EXPECT_NE(error_of(b).find("format version 7"), std::string::npos) << error_of(b);
  b = bytes();
  b.resize(b.size() - 100);
  EXPECT_NE(error_of(b).find("truncated or extended"), std::string::npos);
  b = bytes();
  b.push_back(0);
  EXPECT_NE(error_of(b).find("truncated or extended"), std::string::npos);
  b = bytes();
  b[b.size() / 2] ^= 0x10;
  EXPECT_NE(error_of(b).find("checksum mismatch"), std::string::npos);
  // A dimension mismatch behind a valid checksum: K stored as 4 x 23.
  ControllerArtifact a = deserialize_artifact(bytes(), "t.tmpc");
  a.K = a.K.leftCols(23).eval();
  b = serialize_artifact(a);
  EXPECT_NE(error_of(b).find("record 'K' is 4x23, expected 4x24"), std::string::npos) << error_of(b);
  EXPECT_NE(error_of({1, 2, 3}).find("truncated"), std::string::npos);
  EXPECT_THROW(load_artifact("/nonexistent/controller.tmpc"), ArtifactError);
}

TEST(Artifact, FuzzedMutationsAndTruncationsAreNeverAccepted) {
  std::mt19937_64 rng(77);
  const std::vector<std::uint8_t>& good = bytes();
  std::uniform_int_distribution<std::size_t> pos(0, good.size() - 1);
  std::uniform_int_distribution<int> val(1, 255);
  int rejected = 0;
  for (int k = 0; k < 1000; ++k) {
    std::vector<std::uint8_t> b = good;
    b[pos(rng)] ^= static_cast<std::uint8_t>(val(rng));  // a real change of one byte
    rejected += !error_of(b).empty();
  }
  for (int k = 0; k < 300; ++k) {
    std::vector<std::uint8_t> b(good.begin(), good.begin() + static_cast<long>(pos(rng)));
    rejected += !error_of(b).empty();
  }
  EXPECT_EQ(rejected, 1300);
}

}  // namespace
}  // namespace tmpc
