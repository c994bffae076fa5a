#include "tmpc/io/protocol.hpp"

#include <cmath>
#include <cstring>

#include "tmpc/model/checksum.hpp"

namespace tmpc::io {

namespace {

constexpr std::size_t kHeader = 6;  // version, type, sequence
constexpr std::size_t kStatePayload = 8 * 21;
constexpr std::size_t kControlPayload = 8 * 4 + 1;

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p[i]) << (8 * i);
  return v;
}
void put_f64(std::uint8_t* p, double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, 8);
  for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(u >> (8 * i));
}
double get_f64(const std::uint8_t* p) {
  std::uint64_t u = 0;
  for (int i = 0; i < 8; ++i) u |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  double d;
  std::memcpy(&d, &u, 8);
  return d;
}

std::size_t finish_encode(std::uint8_t* packet, std::size_t len, std::vector<std::uint8_t>& out) {
  put_u32(packet + len, tmpc::crc32(packet, len));
  len += 4;
  out.resize(len + len / 254 + 2);
  const std::size_t n = cobs_encode(packet, len, out.data());
  out[n] = 0x00;
  out.resize(n + 1);
  return n + 1;
}

}  // namespace

std::size_t cobs_encode(const std::uint8_t* in, std::size_t n, std::uint8_t* out) {
  std::size_t code_pos = 0, o = 1;
  std::uint8_t code = 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (in[i] == 0) {
      out[code_pos] = code;
      code_pos = o++;
      code = 1;
    } else {
      out[o++] = in[i];
      if (++code == 0xFF) {
        out[code_pos] = code;
        code_pos = o++;
        code = 1;
      }
    }
  }
  out[code_pos] = code;
  return o;
}

long cobs_decode(const std::uint8_t* in, std::size_t n, std::uint8_t* out, std::size_t cap) {
  std::size_t i = 0, o = 0;
  while (i < n) {
    const std::uint8_t code = in[i++];
    if (code == 0) return -1;
    for (std::uint8_t k = 1; k < code; ++k) {
      if (i >= n || o >= cap) return -1;
      if (in[i] == 0) return -1;
      out[o++] = in[i++];
    }
    if (code != 0xFF && i < n) {
      if (o >= cap) return -1;
      out[o++] = 0;
    }
  }
  return static_cast<long>(o);
}

std::size_t encode(const StateFrame& f, std::vector<std::uint8_t>& out) {
  std::uint8_t p[kHeader + kStatePayload + 4];
  p[0] = kProtocolVersion;
  p[1] = static_cast<std::uint8_t>(FrameType::State);
  put_u32(p + 2, f.seq);
  put_f64(p + kHeader, f.time);
  for (std::size_t i = 0; i < 20; ++i) put_f64(p + kHeader + 8 * (i + 1), f.x[i]);
  return finish_encode(p, kHeader + kStatePayload, out);
}

std::size_t encode(const ControlFrame& f, std::vector<std::uint8_t>& out) {
  std::uint8_t p[kHeader + kControlPayload + 4];
  p[0] = kProtocolVersion;
  p[1] = static_cast<std::uint8_t>(FrameType::Control);
  put_u32(p + 2, f.seq);
  for (std::size_t i = 0; i < 4; ++i) put_f64(p + kHeader + 8 * i, f.u[i]);
  p[kHeader + 32] = f.flags;
  return finish_encode(p, kHeader + kControlPayload, out);
}

Decoder::Decoder(FrameType expected, StateBounds bounds) : expected_(expected), bounds_(bounds) {}

bool Decoder::push(std::uint8_t byte) {
  if (byte != 0x00) {
    if (n_ < raw_.size()) {
      raw_[n_++] = byte;
    } else {
      overflow_ = true;
    }
    return false;
  }
  const bool ok = finish();
  n_ = 0;
  overflow_ = false;
  return ok;
}

bool Decoder::finish() {
  if (n_ == 0 && !overflow_) return false;  // empty frame: line idle or resync
  if (overflow_) {
    ++stats_.oversize;
    return false;
  }
  const long len = cobs_decode(raw_.data(), n_, packet_.data(), packet_.size());
  if (len < 0) {
    ++stats_.bad_cobs;
    return false;
  }
  const std::size_t L = static_cast<std::size_t>(len);
  if (L < kHeader + 4) {
    ++stats_.bad_length;
    return false;
  }
  if (get_u32(packet_.data() + L - 4) != tmpc::crc32(packet_.data(), L - 4)) {
    ++stats_.bad_crc;
    return false;
  }
  if (packet_[0] != kProtocolVersion) {
    ++stats_.bad_version;
    return false;
  }
  if (packet_[1] != static_cast<std::uint8_t>(expected_)) {
    ++stats_.unknown_type;
    return false;
  }
  const std::size_t payload = expected_ == FrameType::State ? kStatePayload : kControlPayload;
  if (L != kHeader + payload + 4) {
    ++stats_.bad_length;
    return false;
  }
  const std::uint32_t seq = get_u32(packet_.data() + 2);
  const std::uint8_t* p = packet_.data() + kHeader;
  // Decode the values, then the checks common to both types in one order:
  // finite, within physical bounds, newer than the last accepted frame.
  bool finite = true, inside = true;
  if (expected_ == FrameType::State) {
    state_next_.seq = seq;
    state_next_.time = get_f64(p);
    finite = std::isfinite(state_next_.time);
    inside = std::abs(state_next_.time) <= bounds_.time;
    for (std::size_t i = 0; i < 20; ++i) {
      const double v = get_f64(p + 8 * (i + 1));
      const double lim = i < 3 ? bounds_.position : (i < 10 ? bounds_.angle : bounds_.velocity);
      state_next_.x[i] = v;
      finite = finite && std::isfinite(v);
      inside = inside && std::abs(v) <= lim;
    }
  } else {
    control_next_.seq = seq;
    for (std::size_t i = 0; i < 4; ++i) {
      const double v = get_f64(p + 8 * i);
      control_next_.u[i] = v;
      finite = finite && std::isfinite(v);
      inside = inside && std::abs(v) <= 1e3;
    }
    control_next_.flags = p[32];
  }
  long* reject = !finite ? &stats_.non_finite
                 : !inside ? &stats_.out_of_bounds
                 : (have_seq_ && static_cast<std::int32_t>(seq - last_seq_) <= 0) ? &stats_.stale_sequence
                                                                                   : nullptr;
  if (reject != nullptr) {
    ++*reject;
    return false;
  }
  if (expected_ == FrameType::State) {
    state_ = state_next_;
  } else {
    control_ = control_next_;
  }
  if (have_seq_) stats_.sequence_gaps += static_cast<long>(seq - last_seq_ - 1);
  have_seq_ = true;
  last_seq_ = seq;
  ++stats_.accepted;
  return true;
}

}  // namespace tmpc::io
