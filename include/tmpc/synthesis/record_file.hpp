// Binary record container shared by the controller artifact (.tmpc) and its
// explicit-MPC companion (.tmpcx):
//   magic (8 bytes) | version u32 | payload length u64 | records | CRC-32 of all before it
//   record = name (u16 length, bytes) | kind u8 | body
//     matrix: rows u32, cols u32, f64 column-major; text: u64 length, bytes; integer: i64
// All integers little-endian. Readers are strict: unknown, missing, duplicate or
// mis-sized records, a bad magic, version, length or checksum throw RecordFileError
// naming the file and what is wrong.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace tmpc {

class RecordFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using FileMagic = std::array<char, 8>;

class RecordWriter {
 public:
  void matrix(const std::string& name, const Eigen::MatrixXd& m);
  void text(const std::string& name, const std::string& t);
  void integer(const std::string& name, std::int64_t v);
  /// The whole file: header, records, checksum.
  std::vector<std::uint8_t> seal(const FileMagic& magic, std::uint32_t version) const;

 private:
  void name(const std::string& s);
  void le(std::uint64_t v, int bytes);
  std::vector<std::uint8_t> b_;
};

class RecordReader {
 public:
  /// Validates header, version, length and checksum; parses all records.
  /// `what` names the file type in messages ("controller artifact").
  RecordReader(const std::vector<std::uint8_t>& bytes, const FileMagic& magic, std::uint32_t version,
               const std::string& source, const std::string& what);
  std::string text(const std::string& name);
  int integer(const std::string& name, std::int64_t lo, std::int64_t hi);
  /// A finite matrix with `rows` rows and `cols` columns (negative: any).
  const Eigen::MatrixXd& matrix(const std::string& name, Eigen::Index rows, Eigen::Index cols);
  bool has(const std::string& name) const { return recs_.count(name) != 0; }
  /// Throws if a record was never read (an unknown record).
  void finish() const;
  [[noreturn]] void fail(const std::string& what) const;

 private:
  enum Kind : std::uint8_t { kMatrix = 1, kText = 2, kInt = 3 };
  struct Record {
    Kind kind = kMatrix;
    Eigen::MatrixXd m;
    std::string text;
    std::int64_t value = 0;
  };
  const Record& get(const std::string& name, Kind kind);
  std::string source_;
  std::map<std::string, Record> recs_;
  std::set<std::string> used_;
};

/// Largest record file read (the explicit law of a long horizon is tens of MB).
constexpr long kMaxRecordFileBytes = 512L << 20;
/// A regular file of at most kMaxRecordFileBytes; throws RecordFileError naming the path.
std::vector<std::uint8_t> read_binary_file(const std::string& path);
void write_binary_file(const std::string& path, const std::vector<std::uint8_t>& bytes);

}  // namespace tmpc
