// Byte transports for the serial protocol: a serial device in termios raw mode
// (8N1, no flow control, configurable baud, default 921600, the driver's low-latency
// flag where it has one: its absence is not an error) and pseudo-terminal pairs for
// tests and `tmpc hil`. Non-blocking reads; writes retry until all bytes are out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace tmpc::io {

class Transport {
 public:
  virtual ~Transport() = default;
  /// Up to cap bytes that are available now (0: none); -1 on a link error. Never blocks.
  virtual long read_some(std::uint8_t* buf, std::size_t cap) = 0;
  /// Writes all n bytes (waits at most timeout_ms for the device); false on error or timeout.
  virtual bool write_all(const std::uint8_t* buf, std::size_t n, int timeout_ms = 50) = 0;
};

/// A file descriptor (serial device or pseudo-terminal side); closes it.
class FdTransport : public Transport {
 public:
  explicit FdTransport(int fd) : fd_(fd) {}
  ~FdTransport() override;
  FdTransport(const FdTransport&) = delete;
  FdTransport& operator=(const FdTransport&) = delete;
  long read_some(std::uint8_t* buf, std::size_t cap) override;
  bool write_all(const std::uint8_t* buf, std::size_t n, int timeout_ms = 50) override;
  int fd() const { return fd_; }

 private:
  int fd_;
};

struct SerialOpenReport {
  bool low_latency = false;   ///< ASYNC_LOW_LATENCY set
  std::string note;           ///< why not (no such ioctl on this driver, e.g. a pseudo-terminal)
};

/// Opens `path` in raw mode at `baud` (a standard termios rate). Throws
/// std::runtime_error naming the device and the reason.
std::unique_ptr<FdTransport> open_serial(const std::string& path, int baud = 921600, SerialOpenReport* report = nullptr);

/// A pseudo-terminal pair: the master side as a transport, the slave's device path
/// (open it with open_serial, like a real port).
struct PtyPair {
  std::unique_ptr<FdTransport> master;
  std::string slave_path;
};
PtyPair open_pty_pair();

}  // namespace tmpc::io
