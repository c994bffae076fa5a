// termios serial ports and pseudo-terminal pairs (see serial_port.hpp).
#include "tmpc/io/serial_port.hpp"

#include <fcntl.h>
#include <linux/serial.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace tmpc::io {

namespace {

speed_t speed_of(int baud, const std::string& path) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 500000: return B500000;
    case 921600: return B921600;
    case 1000000: return B1000000;
    case 1500000: return B1500000;
    case 2000000: return B2000000;
    case 3000000: return B3000000;
    case 4000000: return B4000000;
    default:
      throw std::runtime_error(path + ": unsupported baud " + std::to_string(baud) +
                               " (use a standard rate: 115200, 460800, 921600, 1000000, 2000000, ...)");
  }
}

void raw_mode(int fd, speed_t speed, const std::string& path) {
  termios t{};
  if (tcgetattr(fd, &t) != 0) throw std::runtime_error(path + ": tcgetattr: " + std::strerror(errno));
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS | PARENB);
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0) {
    throw std::runtime_error(path + ": cannot set the baud rate: " + std::strerror(errno));
  }
  if (tcsetattr(fd, TCSANOW, &t) != 0) throw std::runtime_error(path + ": tcsetattr: " + std::strerror(errno));
  tcflush(fd, TCIOFLUSH);
}

}  // namespace

FdTransport::~FdTransport() {
  if (fd_ >= 0) ::close(fd_);
}

long FdTransport::read_some(std::uint8_t* buf, std::size_t cap) {
  const ssize_t n = ::read(fd_, buf, cap);
  if (n >= 0) return static_cast<long>(n);
  if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return 0;
  return -1;
}

bool FdTransport::write_all(const std::uint8_t* buf, std::size_t n, int timeout_ms) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, buf + done, n - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return false;
    pollfd p{fd_, POLLOUT, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
  }
  return true;
}

std::unique_ptr<FdTransport> open_serial(const std::string& path, int baud, SerialOpenReport* report) {
  const speed_t speed = speed_of(baud, path);
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  auto t = std::make_unique<FdTransport>(fd);
  if (!isatty(fd)) throw std::runtime_error(path + ": not a terminal device");
  raw_mode(fd, speed, path);
  SerialOpenReport r;
  serial_struct ss{};
  if (ioctl(fd, TIOCGSERIAL, &ss) == 0) {
    ss.flags |= ASYNC_LOW_LATENCY;
    r.low_latency = ioctl(fd, TIOCSSERIAL, &ss) == 0;
    if (!r.low_latency) r.note = std::string("low-latency flag refused: ") + std::strerror(errno);
  } else {
    r.note = "no low-latency flag on this driver";
  }
  if (report != nullptr) *report = r;
  return t;
}

PtyPair open_pty_pair() {
  const int m = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (m < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
  PtyPair p;
  p.master = std::make_unique<FdTransport>(m);
  if (grantpt(m) != 0 || unlockpt(m) != 0) throw std::runtime_error(std::string("grantpt/unlockpt: ") + std::strerror(errno));
  char name[128];
  if (ptsname_r(m, name, sizeof(name)) != 0) throw std::runtime_error(std::string("ptsname: ") + std::strerror(errno));
  p.slave_path = name;
  termios t{};
  if (tcgetattr(m, &t) == 0) {  // the master side raw too (no echo, no line discipline)
    cfmakeraw(&t);
    tcsetattr(m, TCSANOW, &t);
  }
  return p;
}

}  // namespace tmpc::io
