// Serial protocol between the plant (or vehicle) and the controller, version 2.
//
// Frame on the wire: COBS(packet) followed by one 0x00 delimiter. Packet, little-endian:
//   u8 version (2) | u8 type | u32 session | u32 sequence | u8 count | payload | u32 CRC-32
//   type 1 STATE   (plant -> controller): f64 time, f64 x[count]   (the measured state)
//   type 2 CONTROL (controller -> plant): f64 u[count], u8 flags
//        flags: bit 0 fallback law, bit 1 safe command (link silent), bit 2 clipped
// `session` is drawn at every process start (draw_session_id(), never 0); `sequence`
// counts the sender's frames within its session from 1.
//
// The decoder takes bytes as they come and returns whole, validated frames. A bad frame
// is counted by reason and dropped, never thrown: framing (COBS, oversize, length, type,
// count), CRC, version, session, sequence, non-finite, bounds. Session and sequence rules
// (no single frame can lock the link out):
//   - the first valid frame adopts its session;
//   - a frame of the current session is accepted when its sequence number is 1 to
//     `sequence_window` ahead of the last accepted one (the frames in between are
//     counted as lost); a duplicate, a replay or one that jumps further is rejected;
//   - rejected frames that follow each other (same session, each 1 to `sequence_window`
//     ahead of the previous) re-anchor the link: `session_confirm` of them for another
//     session (a restarted peer; default 2, so a lone stray frame never switches),
//     `resync_frames` of them within the current session (a sender whose counter
//     jumped). An accepted frame of the current session clears such a run, so a live
//     session keeps the link against another sender.
// Time and jump gates need the model: runtime/state_gate.hpp counts them here too.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tmpc/model/state_layout.hpp"

namespace tmpc::io {

constexpr std::uint8_t kProtocolVersion = 2;
constexpr std::size_t kMaxStateValues = 48;
constexpr std::size_t kMaxControlValues = 16;
constexpr std::size_t kMaxPacket = 512;
static_assert(kMaxStateValues >= static_cast<std::size_t>(kMaxStates), "a state frame carries every measured state");
static_assert(kMaxControlValues >= static_cast<std::size_t>(kMaxInputs), "a control frame carries every input");

enum class FrameType : std::uint8_t { State = 1, Control = 2 };

struct StateFrame {
  std::uint32_t session = 0, seq = 0;
  double time = 0.0;
  std::uint8_t n = 0;                            ///< entries of x in use
  std::array<double, kMaxStateValues> x{};
};

struct ControlFrame {
  std::uint32_t session = 0, seq = 0;
  std::uint8_t n = 0;                            ///< entries of u in use
  std::array<double, kMaxControlValues> u{};
  std::uint8_t flags = 0;
  static constexpr std::uint8_t kFallback = 1, kSafe = 2, kClipped = 4;
};

/// Why a frame was dropped (the end-of-run summary and the telemetry count each).
enum class Reject : std::uint8_t { Crc, Framing, Version, Session, Sequence, NonFinite, Bounds, Time, Jump };
constexpr std::size_t kRejectReasons = 9;
const char* to_string(Reject r);

struct LinkCounts {
  long accepted = 0;
  std::array<long, kRejectReasons> rejected{};
  long lost = 0;             ///< sequence numbers skipped before accepted frames
  long session_changes = 0;  ///< sessions adopted after the first
  long resyncs = 0;          ///< re-anchored sequences (or, in the state gate, tracks)
  long& operator[](Reject r) { return rejected[static_cast<std::size_t>(r)]; }
  long operator[](Reject r) const { return rejected[static_cast<std::size_t>(r)]; }
  long rejected_total() const;
  /// This and `o` added (the decoder's counts and the state gate's).
  LinkCounts plus(const LinkCounts& o) const;
};
/// "412 accepted, 3 rejected (crc 1, jump 2), 5 lost, 1 new session" for reports.
std::string summary(const LinkCounts& c);

/// What a decoder accepts. `bound[i]` limits |value i| (state x or control u).
struct DecoderSettings {
  FrameType type = FrameType::State;
  std::size_t values = 0;          ///< expected count (x entries or u entries)
  std::array<double, kMaxStateValues> bound{};  ///< per value; 0 or less: unbounded
  double time_bound = 1e6;         ///< |time| <= this (state frames), s
  std::uint32_t sequence_window = 1000;
  int resync_frames = 3;
  int session_confirm = 2;
  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// Defaults for a state decoder of `n` values (all bounded by `bound`).
DecoderSettings state_decoder_settings(std::size_t n, double bound = 1e9);
/// Defaults for a control decoder of `m` inputs, each |u| <= bound.
DecoderSettings control_decoder_settings(std::size_t m, double bound = 1e3);

/// Encode into `out` (cleared first); returns the number of bytes (delimiter included).
/// Frames with more values than the protocol carries are clipped to its maximum.
std::size_t encode(const StateFrame& f, std::vector<std::uint8_t>& out);
std::size_t encode(const ControlFrame& f, std::vector<std::uint8_t>& out);

/// Streaming decoder for one direction. Preallocated; push() never allocates or throws.
class Decoder {
 public:
  /// Throws std::invalid_argument for bad settings.
  explicit Decoder(DecoderSettings s);
  /// Feed one byte; returns true when a frame was completed and accepted.
  bool push(std::uint8_t byte);
  const StateFrame& state() const { return state_; }
  const ControlFrame& control() const { return control_; }
  /// Of the last accepted frame: it adopted a new session (the peer restarted) or
  /// re-anchored the sequence; sequence numbers skipped before it.
  bool new_session() const { return new_session_; }
  bool resynced() const { return resynced_; }
  long skipped() const { return skipped_; }
  std::uint32_t session() const { return session_; }
  const LinkCounts& counts() const { return counts_; }
  const DecoderSettings& settings() const { return s_; }

 private:
  bool finish();
  bool sequence_ok(std::uint32_t session, std::uint32_t seq);
  DecoderSettings s_;
  std::array<std::uint8_t, kMaxPacket + kMaxPacket / 254 + 2> raw_{};
  std::array<std::uint8_t, kMaxPacket> packet_{};
  std::size_t n_ = 0;
  bool overflow_ = false;
  bool have_session_ = false;
  std::uint32_t session_ = 0, last_seq_ = 0;
  // A run of rejected frames that follow each other (a candidate re-anchoring).
  bool have_run_ = false;
  std::uint32_t run_session_ = 0, run_seq_ = 0;
  int run_length_ = 0;
  bool new_session_ = false, resynced_ = false;
  long skipped_ = 0;
  StateFrame state_, state_next_;
  ControlFrame control_, control_next_;
  LinkCounts counts_;
};

/// A fresh session id for this process start: random, never 0.
std::uint32_t draw_session_id();

/// COBS (consistent overhead byte stuffing), exposed for tests.
std::size_t cobs_encode(const std::uint8_t* in, std::size_t n, std::uint8_t* out);
/// Returns the decoded length, or -1 for malformed input.
long cobs_decode(const std::uint8_t* in, std::size_t n, std::uint8_t* out, std::size_t cap);

}  // namespace tmpc::io
