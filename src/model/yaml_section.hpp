// Internal: checked reading of a YAML mapping for the loaders of the design config
// (config.cpp, trajectory_config.cpp) and of scenarios (sim/scenario.cpp): every key
// read or reported unknown by finish(), duplicates and non-scalar keys refused, values
// range- and type-checked, every message naming the file and the dotted key.
#pragma once

#include <cmath>
#include <initializer_list>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "tmpc/model/config.hpp"

namespace tmpc::detail {

/// A YAML mapping with its dotted path; every access is checked and every key
/// that is not read is reported as unknown by finish().
class Section {
 public:
  Section(YAML::Node node, std::string path, const std::string& file)
      : node_(std::move(node)), path_(std::move(path)), file_(file) {
    if (!node_ || !node_.IsMap()) fail(path_.empty() ? "(top level)" : path_, "expected a mapping");
    // yaml-cpp keeps every duplicate and node[k] returns the first: a later value of
    // the same key would be ignored silently. Keys must also be plain names.
    std::set<std::string> seen;
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar()) {
        fail(path_.empty() ? "(top level)" : path_,
             "a key must be a plain name, found a " + std::string(kv.first.IsSequence() ? "list" : "mapping") +
                 " at line " + std::to_string(kv.first.Mark().line + 1));
      }
      const std::string k = kv.first.Scalar();
      if (!seen.insert(k).second) {
        fail(key(k), "duplicate key (again at line " + std::to_string(kv.first.Mark().line + 1) +
                         "; only one value is allowed)");
      }
    }
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw ConfigError(file_ + ": " + key + ": " + what);
  }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  YAML::Node raw(const std::string& k) {
    used_.insert(k);
    YAML::Node n = node_[k];
    if (!n) fail(key(k), "missing");
    return n;
  }
  bool has(const std::string& k) const { return static_cast<bool>(node_[k]); }

  Section section(const std::string& k) { return Section(raw(k), key(k), file_); }

  double number(const std::string& k) {
    YAML::Node n = raw(k);
    return to_number(n, key(k));
  }
  double number_in(const std::string& k, double lo, double hi) {
    const double v = number(k);
    if (v < lo || v > hi) {
      std::ostringstream os;
      os << "out of range: " << v << " not in [" << lo << ", " << hi << "]";
      fail(key(k), os.str());
    }
    return v;
  }
  /// A whole number in [lo, hi] ("horizon: 20.7" is an error, not 20).
  int integer_in(const std::string& k, long lo, long hi) {
    const double v = number(k);
    if (std::floor(v) != v) fail(key(k), "expected a whole number, got " + fmt(v));
    if (v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
      fail(key(k), "out of range: " + fmt(v) + " not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return static_cast<int>(v);
  }
  double positive(const std::string& k) {
    const double v = number(k);
    if (!(v > 0.0)) fail(key(k), "must be positive (got " + fmt(v) + ")");
    return v;
  }
  std::string text(const std::string& k, std::initializer_list<const char*> allowed) {
    YAML::Node n = raw(k);
    if (!n.IsScalar()) fail(key(k), "expected a string");
    const std::string s = n.as<std::string>();
    std::string list;
    for (const char* a : allowed) {
      if (s == a) return s;
      list += list.empty() ? a : std::string(", ") + a;
    }
    fail(key(k), "unknown value '" + s + "' (expected one of: " + list + ")");
  }
  bool flag(const std::string& k) {
    YAML::Node n = raw(k);
    if (!n.IsScalar()) fail(key(k), "expected true or false");
    const std::string v = n.as<std::string>();
    if (v == "true") return true;
    if (v == "false") return false;
    fail(key(k), "expected true or false, got '" + v + "'");
  }
  std::vector<double> vector(const std::string& k, std::size_t n) {
    return vector_of(raw(k), key(k), n);
  }
  std::vector<double> vector_of(const YAML::Node& node, const std::string& name, std::size_t n) const {
    if (!node.IsSequence()) fail(name, "expected a list of " + std::to_string(n) + " numbers");
    if (node.size() != n) {
      fail(name, "expected " + std::to_string(n) + " values, got " + std::to_string(node.size()));
    }
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = to_number(node[i], name + "[" + std::to_string(i) + "]");
    return out;
  }

  /// A list of numbers of any length (at least `min_size`).
  std::vector<double> list(const std::string& k, std::size_t min_size = 1) {
    YAML::Node node = raw(k);
    if (!node.IsSequence()) fail(key(k), "expected a list of numbers");
    if (node.size() < min_size) {
      fail(key(k), "expected at least " + std::to_string(min_size) + " values, got " + std::to_string(node.size()));
    }
    return vector_of(node, key(k), node.size());
  }
  /// A matrix as a list of rows of `cols` numbers each (cols < 0: any, equal for all rows).
  Eigen::MatrixXd matrix(const std::string& k, long rows, long cols) {
    YAML::Node node = raw(k);
    const std::string name = key(k);
    if (!node.IsSequence() || node.size() == 0) fail(name, "expected a list of rows");
    if (rows >= 0 && static_cast<long>(node.size()) != rows) {
      fail(name, "expected " + std::to_string(rows) + " rows, got " + std::to_string(node.size()));
    }
    const long c = cols >= 0 ? cols : (node[0].IsSequence() ? static_cast<long>(node[0].size()) : -1);
    if (c < 1) fail(name, "expected rows that are lists of numbers");
    Eigen::MatrixXd m(static_cast<Eigen::Index>(node.size()), c);
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::vector<double> r = vector_of(node[i], name + "[" + std::to_string(i) + "]", static_cast<std::size_t>(c));
      for (long j = 0; j < c; ++j) m(static_cast<Eigen::Index>(i), j) = r[static_cast<std::size_t>(j)];
    }
    return m;
  }
  /// Any string.
  std::string string(const std::string& k) {
    YAML::Node n = raw(k);
    if (!n.IsScalar()) fail(key(k), "expected a string");
    return n.Scalar();
  }
  /// A list of strings.
  std::vector<std::string> strings(const std::string& k) {
    YAML::Node n = raw(k);
    if (!n.IsSequence()) fail(key(k), "expected a list of names");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (!n[i].IsScalar()) fail(key(k) + "[" + std::to_string(i) + "]", "expected a name");
      out.push_back(n[i].Scalar());
    }
    return out;
  }
  /// Sections of a list of mappings ("steps: [{time: .., force: ..}, ...]").
  std::vector<Section> sections(const std::string& k) {
    YAML::Node n = raw(k);
    if (!n.IsSequence()) fail(key(k), "expected a list");
    std::vector<Section> out;
    for (std::size_t i = 0; i < n.size(); ++i) out.emplace_back(n[i], key(k) + "[" + std::to_string(i) + "]", file_);
    return out;
  }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

  /// Report keys that were never read (typos, unsupported options).
  void finish() const {
    for (const auto& kv : node_) {
      const std::string k = kv.first.Scalar();
      if (used_.count(k) == 0) fail(key(k), "unknown key");
    }
  }

 private:

 public:
  static std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

 private:
  double to_number(const YAML::Node& n, const std::string& name) const {
    if (!n.IsScalar()) fail(name, "expected a number");
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(name, "expected a number, got '" + n.as<std::string>() + "'");
    }
    if (!std::isfinite(v)) fail(name, "must be finite (got " + n.as<std::string>() + ")");
    return v;
  }

  YAML::Node node_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> used_;
};

/// Where a YAML stream's first two documents start (the parser run for at most two).
/// yaml-cpp 0.7's LoadAll loops forever, allocating, on a stray ',' at the top level
/// (jbeder/yaml-cpp#1040, fixed upstream by #1319): its parser returns the same empty
/// document again and again without consuming the token. Two documents that start at
/// the same place are that parser stuck, not a second document.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::vector<YAML::Mark> starts;
  void OnDocumentStart(const YAML::Mark& m) override { starts.push_back(m); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

/// The text of a YAML file as one document (a second document is an error naming its line).
inline YAML::Node load_single_document(const std::string& text, const std::string& source) {
  DocumentStarts starts;
  YAML::Node doc;
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    for (int i = 0; i < 2 && parser.HandleNextDocument(starts); ++i) {
    }
    if (starts.starts.size() == 2 && starts.starts[1].pos == starts.starts[0].pos) {
      throw ConfigError(source + ": YAML syntax error: yaml-cpp: error at line " +
                        std::to_string(starts.starts[0].line + 1) + ", column " +
                        std::to_string(starts.starts[0].column + 1) +
                        ": a token that starts no node (a stray ',' outside a flow sequence or map?)");
    }
    if (starts.starts.size() < 2) doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ": YAML syntax error: " + e.what());
  }
  if (starts.starts.empty()) throw ConfigError(source + ": (top level): the file is empty");
  if (starts.starts.size() > 1) {
    throw ConfigError(source + ": a second YAML document starts at line " + std::to_string(starts.starts[1].line + 1) +
                      " (a file is one document; remove the '---' or split the file)");
  }
  return doc;
}

inline Eigen::Vector3d vec3(Section& s, const std::string& k) {
  const auto v = s.vector(k, 3);
  return {v[0], v[1], v[2]};
}

}  // namespace tmpc::detail
