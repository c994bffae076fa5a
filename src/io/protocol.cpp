// Serial protocol, version 2 (see protocol.hpp).
#include "tmpc/io/protocol.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>

#include "tmpc/model/checksum.hpp"

namespace tmpc::io {

namespace {

constexpr std::size_t kHeader = 11;  // version, type, session, sequence, count

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

void put_header(std::uint8_t* p, FrameType type, std::uint32_t session, std::uint32_t seq, std::size_t count) {
  p[0] = kProtocolVersion;
  p[1] = static_cast<std::uint8_t>(type);
  put_u32(p + 2, session);
  put_u32(p + 6, seq);
  p[10] = static_cast<std::uint8_t>(count);
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

/// Signed distance from a to b in sequence space (wraps at 2^32).
long ahead(std::uint32_t b, std::uint32_t a) { return static_cast<long>(static_cast<std::int32_t>(b - a)); }

}  // namespace

const char* to_string(Reject r) {
  switch (r) {
    case Reject::Crc: return "crc";
    case Reject::Framing: return "framing";
    case Reject::Version: return "version";
    case Reject::Session: return "session";
    case Reject::Sequence: return "sequence";
    case Reject::NonFinite: return "non_finite";
    case Reject::Bounds: return "bounds";
    case Reject::Time: return "time";
    case Reject::Jump: return "jump";
  }
  return "?";
}

long LinkCounts::rejected_total() const {
  long s = 0;
  for (long r : rejected) s += r;
  return s;
}

LinkCounts LinkCounts::plus(const LinkCounts& o) const {
  LinkCounts c = *this;
  c.accepted = accepted + o.accepted;
  for (std::size_t i = 0; i < kRejectReasons; ++i) c.rejected[i] += o.rejected[i];
  c.lost += o.lost;
  c.session_changes += o.session_changes;
  c.resyncs += o.resyncs;
  return c;
}

std::string summary(const LinkCounts& c) {
  std::string s = std::to_string(c.accepted) + " accepted, " + std::to_string(c.rejected_total()) + " rejected";
  std::string why;
  for (std::size_t i = 0; i < kRejectReasons; ++i) {
    if (c.rejected[i] == 0) continue;
    why += (why.empty() ? "" : ", ") + std::string(to_string(static_cast<Reject>(i))) + " " + std::to_string(c.rejected[i]);
  }
  if (!why.empty()) s += " (" + why + ")";
  s += ", " + std::to_string(c.lost) + " lost";
  if (c.session_changes > 0) s += ", " + std::to_string(c.session_changes) + " new session(s)";
  if (c.resyncs > 0) s += ", " + std::to_string(c.resyncs) + " resync(s)";
  return s;
}

void DecoderSettings::validate() const {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("decoder settings: " + what);
  };
  const std::size_t cap = type == FrameType::State ? kMaxStateValues : kMaxControlValues;
  need(values >= 1 && values <= cap, "values must be in [1, " + std::to_string(cap) + "], got " + std::to_string(values));
  need(time_bound > 0.0, "time_bound must be positive");
  need(sequence_window >= 1 && sequence_window < (1u << 30), "sequence_window must be in [1, 2^30)");
  need(resync_frames >= 2, "resync_frames must be >= 2 (one frame must never re-anchor the link)");
  need(session_confirm >= 1, "session_confirm must be >= 1");
}

DecoderSettings state_decoder_settings(std::size_t n, double bound) {
  DecoderSettings s;
  s.type = FrameType::State;
  s.values = n;
  s.bound.fill(bound);
  return s;
}

DecoderSettings control_decoder_settings(std::size_t m, double bound) {
  DecoderSettings s;
  s.type = FrameType::Control;
  s.values = m;
  s.bound.fill(bound);
  return s;
}

std::uint32_t draw_session_id() {
  std::random_device rd;
  std::seed_seq seed{rd(), rd(), static_cast<unsigned>(::getpid()),
                     static_cast<unsigned>(std::chrono::steady_clock::now().time_since_epoch().count())};
  std::mt19937 g(seed);
  std::uint32_t id = 0;
  while (id == 0) id = static_cast<std::uint32_t>(g());
  return id;
}

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
  std::uint8_t p[kHeader + 8 * (kMaxStateValues + 1) + 4];
  const std::size_t n = std::min<std::size_t>(f.n, kMaxStateValues);
  put_header(p, FrameType::State, f.session, f.seq, n);
  put_f64(p + kHeader, f.time);
  for (std::size_t i = 0; i < n; ++i) put_f64(p + kHeader + 8 * (i + 1), f.x[i]);
  return finish_encode(p, kHeader + 8 * (n + 1), out);
}

std::size_t encode(const ControlFrame& f, std::vector<std::uint8_t>& out) {
  std::uint8_t p[kHeader + 8 * kMaxControlValues + 1 + 4];
  const std::size_t n = std::min<std::size_t>(f.n, kMaxControlValues);
  put_header(p, FrameType::Control, f.session, f.seq, n);
  for (std::size_t i = 0; i < n; ++i) put_f64(p + kHeader + 8 * i, f.u[i]);
  p[kHeader + 8 * n] = f.flags;
  return finish_encode(p, kHeader + 8 * n + 1, out);
}

Decoder::Decoder(DecoderSettings s) : s_(s) { s_.validate(); }

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

bool Decoder::sequence_ok(std::uint32_t session, std::uint32_t seq) {
  new_session_ = resynced_ = false;
  skipped_ = 0;
  const long window = static_cast<long>(s_.sequence_window);
  if (!have_session_) {
    have_session_ = true;
    session_ = session;
    last_seq_ = seq;
    new_session_ = true;
    have_run_ = false;
    return true;
  }
  if (session == session_) {
    const long d = ahead(seq, last_seq_);
    if (d >= 1 && d <= window) {
      skipped_ = d - 1;
      counts_.lost += skipped_;
      last_seq_ = seq;
      have_run_ = false;  // the live session keeps the link
      return true;
    }
  }
  // Not acceptable on its own: does it continue a run of rejected frames?
  const long d_run = ahead(seq, run_seq_);
  if (have_run_ && session == run_session_ && d_run >= 1 && d_run <= window) {
    ++run_length_;
  } else {
    have_run_ = session != 0;
    run_session_ = session;
    run_length_ = 1;
  }
  run_seq_ = seq;
  const int needed = session == session_ ? s_.resync_frames : s_.session_confirm;
  if (have_run_ && run_length_ >= needed) {
    if (session == session_) {
      resynced_ = true;
      ++counts_.resyncs;
    } else {
      new_session_ = true;
      ++counts_.session_changes;
    }
    session_ = session;
    last_seq_ = seq;
    have_run_ = false;
    return true;
  }
  ++counts_[session == session_ ? Reject::Sequence : Reject::Session];
  return false;
}

bool Decoder::finish() {
  if (n_ == 0 && !overflow_) return false;  // empty frame: line idle or resync
  if (overflow_) {
    ++counts_[Reject::Framing];
    return false;
  }
  const long len = cobs_decode(raw_.data(), n_, packet_.data(), packet_.size());
  if (len < 0 || static_cast<std::size_t>(len) < kHeader + 4) {
    ++counts_[Reject::Framing];
    return false;
  }
  const std::size_t L = static_cast<std::size_t>(len);
  if (get_u32(packet_.data() + L - 4) != tmpc::crc32(packet_.data(), L - 4)) {
    ++counts_[Reject::Crc];
    return false;
  }
  if (packet_[0] != kProtocolVersion) {
    ++counts_[Reject::Version];
    return false;
  }
  const std::size_t count = packet_[10];
  const bool state = s_.type == FrameType::State;
  const std::size_t payload = state ? 8 * (count + 1) : 8 * count + 1;
  if (packet_[1] != static_cast<std::uint8_t>(s_.type) || count != s_.values || L != kHeader + payload + 4) {
    ++counts_[Reject::Framing];
    return false;
  }
  const std::uint32_t session = get_u32(packet_.data() + 2);
  const std::uint32_t seq = get_u32(packet_.data() + 6);
  const std::uint8_t* p = packet_.data() + kHeader;
  // Decode the values, then in one order: finite, within bounds, session and sequence.
  bool finite = true, inside = true;
  auto check = [&](double v, std::size_t i) {
    finite = finite && std::isfinite(v);
    inside = inside && (s_.bound[i] <= 0.0 || std::abs(v) <= s_.bound[i]);
  };
  if (state) {
    state_next_.session = session;
    state_next_.seq = seq;
    state_next_.n = static_cast<std::uint8_t>(count);
    state_next_.time = get_f64(p);
    finite = std::isfinite(state_next_.time);
    inside = std::abs(state_next_.time) <= s_.time_bound;
    for (std::size_t i = 0; i < count; ++i) {
      state_next_.x[i] = get_f64(p + 8 * (i + 1));
      check(state_next_.x[i], i);
    }
  } else {
    control_next_.session = session;
    control_next_.seq = seq;
    control_next_.n = static_cast<std::uint8_t>(count);
    for (std::size_t i = 0; i < count; ++i) {
      control_next_.u[i] = get_f64(p + 8 * i);
      check(control_next_.u[i], i);
    }
    control_next_.flags = p[8 * count];
  }
  if (!finite || !inside) {
    ++counts_[!finite ? Reject::NonFinite : Reject::Bounds];
    return false;
  }
  if (session == 0) {
    ++counts_[Reject::Session];
    return false;
  }
  if (!sequence_ok(session, seq)) return false;
  if (state) {
    state_ = state_next_;
  } else {
    control_ = control_next_;
  }
  ++counts_.accepted;
  return true;
}

}  // namespace tmpc::io
