// tmpc compare A/metrics.json B/metrics.json: the thesis-style comparison (6.1),
// improvement = (A - B) / A in percent for each metric, and, when both files are Monte
// Carlo campaigns, Welch's t-test over their per-run values.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "tmpc/metrics/campaign.hpp"

namespace tmpc::cli {

namespace {

struct Metrics {
  std::string path;
  nlohmann::json summary;            // the single run, or the campaign mean
  std::vector<nlohmann::json> runs;  // campaign runs (empty for a single run)
};

Metrics load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": not JSON: " + e.what());
  }
  Metrics m;
  m.path = path;
  if (j.contains("runs") && j["runs"].is_array()) {
    for (const auto& r : j["runs"]) m.runs.push_back(r);
    m.summary = j.at("mean");
  } else {
    m.summary = j;
  }
  if (!m.summary.contains("rmse")) throw std::runtime_error(path + ": no 'rmse' (not a tmpc metrics.json)");
  return m;
}

double at(const nlohmann::json& j, const std::string& pointer) {
  const nlohmann::json::json_pointer p(pointer);
  if (!j.contains(p) || !j.at(p).is_number()) throw std::runtime_error("metrics.json: missing number " + pointer);
  return j.at(p).get<double>();
}

void run_compare(const std::string& a_path, const std::string& b_path) {
  const Metrics a = load(a_path), b = load(b_path);
  const bool test = a.runs.size() >= 2 && b.runs.size() >= 2;
  std::printf("A = %s (%s), B = %s (%s)\n", a.path.c_str(),
              a.runs.empty() ? "one run" : (std::to_string(a.runs.size()) + " runs, mean").c_str(), b.path.c_str(),
              b.runs.empty() ? "one run" : (std::to_string(b.runs.size()) + " runs, mean").c_str());
  std::printf("%-28s %12s %12s %10s%s\n", "metric", "A", "B", "(A-B)/A", test ? "   Welch t      dof        p" : "");
  std::vector<std::string> keys;
  for (const char* c : {"x", "y", "z", "phi", "theta", "psi", "gamma_1", "gamma_2", "alpha_r", "alpha_l"}) {
    keys.push_back(std::string("/rmse/") + c);
  }
  for (const char* c : {"f_r", "f_l", "tau_r", "tau_l"}) keys.push_back(std::string("/tcv/") + c);
  for (const char* k : {"/solve_us/p50", "/solve_us/p99", "/solve_us/max", "/fallback_periods", "/clipped_periods",
                        "/tube_exits/total", "/state_constraint_violations"}) {
    keys.emplace_back(k);
  }
  for (const std::string& k : keys) {
    if (!a.summary.contains(nlohmann::json::json_pointer(k)) || !b.summary.contains(nlohmann::json::json_pointer(k))) {
      continue;  // e.g. coordinate names of another model
    }
    const double va = at(a.summary, k), vb = at(b.summary, k);
    const std::string change = va != 0.0 ? std::to_string(100.0 * (va - vb) / va).substr(0, 7) + " %" : "-";
    std::printf("%-28s %12.5g %12.5g %10s", k.c_str() + 1, va, vb, change.c_str());
    if (test) {
      std::vector<double> ra, rb;
      for (const auto& r : a.runs) ra.push_back(at(r, k));
      for (const auto& r : b.runs) rb.push_back(at(r, k));
      const WelchTest w = welch_t_test(ra, rb);
      std::printf("   %8.3f %8.2f %8.2g%s", w.t, w.dof, w.p, w.p < 0.05 ? " *" : "");
    }
    std::printf("\n");
  }
  if (test) std::printf("* difference significant at the 5 %% level (two-sided)\n");
}

}  // namespace

void register_compare(CLI::App& app) {
  auto a = std::make_shared<std::string>();
  auto b = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand("compare", "Compare two metrics.json (thesis 6.1; Welch t-test over Monte Carlo runs)");
  sub->add_option("A", *a, "first metrics.json (the baseline)")->required();
  sub->add_option("B", *b, "second metrics.json")->required();
  sub->callback([a, b]() { run_compare(*a, *b); });
}

}  // namespace tmpc::cli
