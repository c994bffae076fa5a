// tmpc explicit --controller FILE.tmpc [--out FILE.tmpcx] [--horizon N] [--control-horizon M]
//   [--domain-fraction F] [--max-regions R] [--time-limit S] [--json]
// Builds the explicit tube MPC law (mpQP partition, affine laws, search tree) of an
// artifact and writes its companion file; `tmpc design --explicit` calls the same code.
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc::cli {

ExplicitOptions explicit_options_from(const ExplicitSettings& e) {
  ExplicitOptions o;
  o.N = e.horizon;
  o.M = e.control_horizon;
  o.domain_fraction = e.domain_fraction;
  o.mpqp.max_regions = e.max_regions;
  o.mpqp.time_limit_s = e.time_limit_s;
  return o;
}

std::string explicit_summary_json(const ExplicitLaw& law) {
  const MpQpStats& s = law.stats;
  const SearchTreeStats& t = law.tree.stats;
  std::size_t rows = law.table.k.size();
  nlohmann::json j = {{"horizon", law.N},
                      {"control_horizon", law.M},
                      {"domain_fraction", law.domain_fraction},
                      {"regions", law.regions()},
                      {"complete", s.complete},
                      {"stop_reason", s.stop_reason},
                      {"build_seconds", s.seconds},
                      {"qp_solves", s.qp_solves},
                      {"lps", s.lps},
                      {"halfspaces", rows},
                      {"halfspaces_per_region", law.regions() > 0 ? static_cast<double>(rows) / law.regions() : 0.0},
                      {"degeneracy", {{"lower_dimensional", s.lower_dimensional}, {"licq_reduced", s.licq_reduced},
                                      {"perturbed", s.perturbed}, {"unresolved_facets", s.unresolved_facets}}},
                      {"coverage", {{"holes_found", s.holes_found}, {"final_pass_located", s.coverage_checked}}},
                      {"tree", {{"nodes", t.nodes}, {"leaves", t.leaves}, {"depth", t.depth},
                                {"hyperplanes", t.hyperplanes}, {"max_leaf_regions", t.max_leaf_regions},
                                {"lps", t.lps}, {"seconds", t.seconds}}},
                      {"memory_bytes", law.memory_bytes()}};
  return j.dump(2);
}

void print_explicit_summary(const ExplicitLaw& law, const std::string& path) {
  const MpQpStats& s = law.stats;
  const SearchTreeStats& t = law.tree.stats;
  std::printf("explicit law: N = %d, M = %d, parameter box %.3g of x_bar: %d regions, %s, %.1f s (%d QPs, %d LPs)\n",
              law.N, law.M, law.domain_fraction, law.regions(), s.complete ? "complete" : "INCOMPLETE", s.seconds,
              s.qp_solves, s.lps);
  if (!s.complete) std::printf("  gave up: %s\n", s.stop_reason.c_str());
  std::printf("  %.1f halfspaces a region; degeneracy: %d lower-dimensional active sets, %d dependent sets reduced, "
              "%d points perturbed, %d facets unresolved; coverage: %d holes refilled\n",
              law.regions() > 0 ? static_cast<double>(law.table.k.size()) / law.regions() : 0.0, s.lower_dimensional,
              s.licq_reduced, s.perturbed, s.unresolved_facets, s.holes_found);
  std::printf("  search tree: %d nodes, depth %d, %d hyperplanes, at most %d regions a leaf, %.1f s\n", t.nodes,
              t.depth, t.hyperplanes, t.max_leaf_regions, t.seconds);
  std::printf("  online data %.1f KiB -> %s\n", law.memory_bytes() / 1024.0, path.c_str());
}

namespace {

struct ExplicitCli {
  std::string controller, out, report;
  int N = 0, M = 0, max_regions = 0;
  double fraction = 0.0, time_limit = 0.0;
};

void run_explicit(const ExplicitCli& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  // Defaults from the artifact's own config, overridden by the flags.
  const Config cfg = load_config_from_string(a.config_text, o.controller + " (embedded config)");
  ExplicitOptions opt = explicit_options_from(cfg.explicit_mpc);
  if (o.N > 0) opt.N = o.N;
  if (o.M > 0) opt.M = o.M;
  if (o.fraction > 0.0) opt.domain_fraction = o.fraction;
  if (o.max_regions > 0) opt.mpqp.max_regions = o.max_regions;
  if (o.time_limit > 0.0) opt.mpqp.time_limit_s = o.time_limit;
  const ExplicitLaw law = build_explicit_law(a, opt);
  const std::string out = o.out.empty() ? explicit_path_for(o.controller) : o.out;
  save_explicit(law, out);
  print_explicit_summary(law, out);
  if (!o.report.empty()) {
    std::ofstream r(o.report);
    if (!r) throw std::runtime_error(o.report + ": cannot write");
    r << explicit_summary_json(law) << "\n";
  }
}

}  // namespace

void register_explicit(CLI::App& app) {
  auto o = std::make_shared<ExplicitCli>();
  CLI::App* sub = app.add_subcommand("explicit", "Build the explicit tube MPC law (mpQP partition and search tree)");
  sub->add_option("--controller", o->controller, "controller artifact")->required()->check(CLI::ExistingFile);
  sub->add_option("--out", o->out, "companion file to write (default: CONTROLLER + 'x')");
  sub->add_option("--report", o->report, "JSON summary to write");
  sub->add_option("--horizon", o->N, "N of the explicit QP (default: the config's explicit.horizon)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--control-horizon", o->M, "M <= N")->check(CLI::PositiveNumber);
  sub->add_option("--domain-fraction", o->fraction, "parameter box as a fraction of x_bar")->check(CLI::Range(1e-6, 1.0));
  sub->add_option("--max-regions", o->max_regions, "give up beyond this many regions")->check(CLI::PositiveNumber);
  sub->add_option("--time-limit", o->time_limit, "give up after this many seconds")->check(CLI::PositiveNumber);
  sub->callback([o]() { run_explicit(*o); });
}

}  // namespace tmpc::cli
