// Record container: writer and strict reader (format in record_file.hpp).
#include "tmpc/synthesis/record_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "tmpc/model/checksum.hpp"

namespace tmpc {

namespace {

constexpr std::size_t kHeader = 20;  // magic 8 + version 4 + payload length 8

std::uint64_t read_le(const std::uint8_t* p, int k) {
  std::uint64_t v = 0;
  for (int i = 0; i < k; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

}  // namespace

void RecordWriter::le(std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

void RecordWriter::name(const std::string& s) {
  le(s.size(), 2);
  b_.insert(b_.end(), s.begin(), s.end());
}

void RecordWriter::matrix(const std::string& n, const Eigen::MatrixXd& m) {
  name(n);
  le(1, 1);
  le(static_cast<std::uint64_t>(m.rows()), 4);
  le(static_cast<std::uint64_t>(m.cols()), 4);
  for (Eigen::Index j = 0; j < m.cols(); ++j) {
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      std::uint64_t u;
      const double v = m(i, j);
      std::memcpy(&u, &v, 8);
      le(u, 8);
    }
  }
}

void RecordWriter::text(const std::string& n, const std::string& t) {
  name(n);
  le(2, 1);
  le(t.size(), 8);
  b_.insert(b_.end(), t.begin(), t.end());
}

void RecordWriter::integer(const std::string& n, std::int64_t v) {
  name(n);
  le(3, 1);
  le(static_cast<std::uint64_t>(v), 8);
}

std::vector<std::uint8_t> RecordWriter::seal(const FileMagic& magic, std::uint32_t version) const {
  std::vector<std::uint8_t> out;
  out.reserve(kHeader + b_.size() + 4);
  for (char c : magic) out.push_back(static_cast<std::uint8_t>(c));
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(version >> (8 * i)));
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(b_.size()) >> (8 * i)));
  out.insert(out.end(), b_.begin(), b_.end());
  const std::uint32_t crc = crc32(out.data(), out.size());
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
  return out;
}

RecordReader::RecordReader(const std::vector<std::uint8_t>& bytes, const FileMagic& magic, std::uint32_t version,
                           const std::string& source, const std::string& what)
    : source_(source) {
  if (bytes.size() < kHeader + 4) {
    throw RecordFileError(source + ": truncated: " + std::to_string(bytes.size()) + " bytes, a " + what +
                          " has at least " + std::to_string(kHeader + 4));
  }
  if (std::memcmp(bytes.data(), magic.data(), 8) != 0) throw RecordFileError(source + ": not a tmpc " + what + " (bad magic)");
  const auto v = static_cast<std::uint32_t>(read_le(bytes.data() + 8, 4));
  if (v != version) {
    throw RecordFileError(source + ": format version " + std::to_string(v) + ", this build reads version " +
                          std::to_string(version) + " (rebuild the " + what + " with this tmpc)");
  }
  const std::uint64_t payload = read_le(bytes.data() + 12, 8);
  if (payload > bytes.size() || kHeader + payload + 4 != bytes.size()) {
    throw RecordFileError(source + ": size mismatch: the header announces " + std::to_string(payload) +
                          " payload bytes, the file has " + std::to_string(bytes.size()) +
                          " bytes in all (truncated or extended)");
  }
  if (crc32(bytes.data(), kHeader + payload) != static_cast<std::uint32_t>(read_le(bytes.data() + kHeader + payload, 4))) {
    throw RecordFileError(source + ": checksum mismatch (the file is corrupt)");
  }
  const std::uint8_t* p = bytes.data() + kHeader;
  const std::size_t n = payload;
  std::size_t pos = 0;
  auto failp = [&](const std::string& m) {
    throw RecordFileError(source + ": " + m + " (at payload byte " + std::to_string(pos) + ")");
  };
  auto take = [&](std::size_t k) {
    if (n - pos < k) failp("record runs past the end of the payload");
    const std::uint8_t* q = p + pos;
    pos += k;
    return q;
  };
  while (pos < n) {
    const std::size_t len = read_le(take(2), 2);
    const std::uint8_t* nm = take(len);
    std::string name(reinterpret_cast<const char*>(nm), len);
    Record r;
    const std::uint64_t kind = read_le(take(1), 1);
    if (kind == kMatrix) {
      r.kind = kMatrix;
      const std::uint64_t rows = read_le(take(4), 4), cols = read_le(take(4), 4);
      if (rows > (1u << 24) || cols > (1u << 24) || rows * cols * 8 > n - pos) failp("matrix '" + name + "' too large");
      r.m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
      for (Eigen::Index j = 0; j < r.m.cols(); ++j) {
        for (Eigen::Index i = 0; i < r.m.rows(); ++i) {
          const std::uint64_t u = read_le(take(8), 8);
          std::memcpy(&r.m(i, j), &u, 8);
        }
      }
    } else if (kind == kText) {
      r.kind = kText;
      const std::uint64_t l = read_le(take(8), 8);
      if (l > n - pos) failp("text '" + name + "' runs past the end of the payload");
      const std::uint8_t* t = take(l);
      r.text.assign(reinterpret_cast<const char*>(t), l);
    } else if (kind == kInt) {
      r.kind = kInt;
      r.value = static_cast<std::int64_t>(read_le(take(8), 8));
    } else {
      failp("record '" + name + "' has unknown kind " + std::to_string(kind));
    }
    if (!recs_.emplace(name, std::move(r)).second) failp("duplicate record '" + name + "'");
  }
}

void RecordReader::fail(const std::string& what) const { throw RecordFileError(source_ + ": " + what); }

const RecordReader::Record& RecordReader::get(const std::string& name, Kind kind) {
  auto it = recs_.find(name);
  if (it == recs_.end()) fail("missing record '" + name + "'");
  if (it->second.kind != kind) fail("record '" + name + "' has the wrong kind");
  used_.insert(name);
  return it->second;
}

std::string RecordReader::text(const std::string& name) { return get(name, kText).text; }

int RecordReader::integer(const std::string& name, std::int64_t lo, std::int64_t hi) {
  const std::int64_t v = get(name, kInt).value;
  if (v < lo || v > hi) {
    fail("record '" + name + "' = " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  }
  return static_cast<int>(v);
}

const Eigen::MatrixXd& RecordReader::matrix(const std::string& name, Eigen::Index rows, Eigen::Index cols) {
  const Record& rec = get(name, kMatrix);
  if ((rows >= 0 && rec.m.rows() != rows) || (cols >= 0 && rec.m.cols() != cols)) {
    fail("record '" + name + "' is " + std::to_string(rec.m.rows()) + "x" + std::to_string(rec.m.cols()) + ", expected " +
         (rows >= 0 ? std::to_string(rows) : std::string("any")) + "x" +
         (cols >= 0 ? std::to_string(cols) : std::string("any")));
  }
  if (!rec.m.allFinite()) fail("record '" + name + "' holds non-finite values");
  return rec.m;
}

void RecordReader::finish() const {
  for (const auto& kv : recs_) {
    if (used_.count(kv.first) == 0) fail("unknown record '" + kv.first + "'");
  }
}

std::vector<std::uint8_t> read_binary_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw RecordFileError(path + ": cannot open the file: " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw RecordFileError(path + ": is a directory, not a file");
  if (!S_ISREG(st.st_mode)) throw RecordFileError(path + ": not a regular file (a device, pipe or socket)");
  if (st.st_size > kMaxRecordFileBytes) {
    throw RecordFileError(path + ": " + std::to_string(st.st_size) + " bytes, more than the " +
                          std::to_string(kMaxRecordFileBytes) + " a record file may have");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RecordFileError(path + ": cannot open the file");
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(st.st_size));
  in.read(reinterpret_cast<char*>(bytes.data()), st.st_size);
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return bytes;
}

void write_binary_file(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw RecordFileError(path + ": cannot open for writing");
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw RecordFileError(path + ": write failed");
}

}  // namespace tmpc
