// How the sampled inputs relate: [[ensemble.group]] (inputs whose Sobol'
// indices are taken together) and [[ensemble.correlation]] (inputs drawn
// through a normal copula). Both name inputs as the job does: a group by
// perturbation targets, a correlation by input columns.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/format.hpp"
#include "designs/design_rules.hpp"
#include "job/ensemble_spec.hpp"
#include "job/readers.hpp"
#include "job/toml_view.hpp"

namespace treedyn {
namespace {

// The strings of `key`, each with its node (for the error position).
std::vector<std::pair<std::string, const toml::node*>> string_list(const TomlView& t, std::string_view key,
                                                                   const std::string& what) {
  const toml::node* node = t.table().get(key);
  const toml::array* list = node ? node->as_array() : nullptr;
  if (!list) t.fail(key, "missing or not an array: " + what);
  std::vector<std::pair<std::string, const toml::node*>> out;
  for (const toml::node& e : *list) {
    const auto text = e.value<std::string>();
    if (!text) t.fail_at(&e, key, "expected a string: " + what);
    out.emplace_back(*text, &e);
  }
  return out;
}

// The input dimensions of perturbation p (in the spec's input order).
std::vector<unsigned> dimensions_of(const EnsembleSpec& s, std::size_t p) {
  unsigned first = 0;
  for (std::size_t k = 0; k < p; ++k) first += static_cast<unsigned>(s.perturbations[k].dimensions());
  std::vector<unsigned> out;
  for (int d = 0; d < s.perturbations[p].dimensions(); ++d) out.push_back(first + static_cast<unsigned>(d));
  return out;
}

// The perturbation whose target is `target`, or the error listing them
// (or saying that two perturbations share it, so the name is ambiguous).
std::size_t perturbation_named(const TomlView& t, const EnsembleSpec& s, const std::string& target,
                               const toml::node* node) {
  std::vector<std::string_view> targets;
  for (const sampling::Perturbation& p : s.perturbations) targets.push_back(p.target);
  const auto first = std::find(targets.begin(), targets.end(), target);
  if (first != targets.end()) {
    if (std::count(targets.begin(), targets.end(), target) > 1)
      t.fail_at(node, "inputs",
                "\"" + target +
                    "\" is the target of more than one [[ensemble.perturbation]]; "
                    "a group cannot tell them apart");
    return static_cast<std::size_t>(first - targets.begin());
  }
  std::string listed;
  for (auto name : targets) listed += " " + std::string(name);
  t.fail_at(node, "inputs",
            "\"" + target + "\" is not the target of an [[ensemble.perturbation]]; they are:" + listed +
                did_you_mean(target, targets));
}

// One [[ensemble.group]]: its name and the dimensions of its targets;
// `taken` marks the perturbations already in a group.
SobolUnit read_group(const TomlView& g, const EnsembleSpec& s, std::vector<std::string>& taken) {
  g.check_keys({"name", "inputs"});
  SobolUnit unit;
  unit.name = g.required_string("name");
  if (unit.name.empty()) g.fail("name", "must not be empty");
  const auto targets = string_list(g, "inputs", "the targets of the group's [[ensemble.perturbation]] entries");
  if (targets.empty()) g.fail("inputs", "list at least one perturbation target");
  for (const auto& [target, node] : targets) {
    const std::size_t p = perturbation_named(g, s, target, node);
    if (!taken[p].empty())
      g.fail_at(node, "inputs",
                "\"" + target + "\" is already in group \"" + taken[p] + "\"; an input belongs to one group");
    taken[p] = unit.name;
    for (unsigned d : dimensions_of(s, p)) unit.inputs.push_back(d);
  }
  std::sort(unit.inputs.begin(), unit.inputs.end());
  return unit;
}

// The units of a grouped Saltelli design: the groups, each multi-input
// perturbation no group lists (an orientation, a sea state's phases) as one,
// and every other input alone; in the order of their first input.
std::vector<SobolUnit> grouped_units(const EnsembleSpec& s, std::vector<SobolUnit> groups,
                                     const std::vector<std::string>& taken) {
  const std::vector<std::string> names = s.input_names();
  for (std::size_t p = 0; p < s.perturbations.size(); ++p) {
    if (!taken[p].empty()) continue;
    const std::vector<unsigned> dims = dimensions_of(s, p);
    if (dims.size() > 1) {
      groups.push_back({s.perturbations[p].target, dims});
    } else {
      for (unsigned d : dims) groups.push_back({names[d], {d}});
    }
  }
  std::sort(groups.begin(), groups.end(),
            [](const SobolUnit& a, const SobolUnit& b) { return a.inputs.front() < b.inputs.front(); });
  return groups;
}

}  // namespace

void read_groups(const TomlView& t, EnsembleSpec& s) {
  const std::vector<TomlView> entries = t.table_array("group");
  const std::vector<std::string> names = s.input_names();
  std::vector<std::string> taken(s.perturbations.size());
  const designs::DesignRules& rules = designs::rules_of(s.design);
  if (entries.empty() && rules.list_input_is_one_factor()) {
    s.sobol_units = grouped_units(s, {}, taken);
    s.grouped = s.sobol_units.size() != names.size();
    return;
  }
  if (entries.empty()) {
    for (unsigned d = 0; d < names.size(); ++d) s.sobol_units.push_back({names[d], {d}});
    return;
  }
  if (!rules.takes_groups())
    entries.front().fail("name",
                         "[[ensemble.group]] sets which inputs Saltelli's or Morris' design moves together; it "
                         "is only for design = \"saltelli\" or \"morris\" (the rank measures are always per input)");
  std::vector<SobolUnit> groups;
  for (const TomlView& g : entries) {
    groups.push_back(read_group(g, s, taken));
    const std::string& name = groups.back().name;
    for (std::size_t k = 0; k + 1 < groups.size(); ++k)
      if (groups[k].name == name) g.fail("name", "group \"" + name + "\" is defined twice; names must be unique");
    const bool target = std::any_of(s.perturbations.begin(), s.perturbations.end(),
                                    [&](const sampling::Perturbation& p) { return p.target == name; });
    if (target || std::find(names.begin(), names.end(), name) != names.end())
      g.fail("name", "\"" + name + "\" is the name of an input; give the group a name of its own");
  }
  s.sobol_units = grouped_units(s, std::move(groups), taken);
  s.grouped = true;
}

namespace {

// Input dimension of the input column `name`, or the error listing them.
unsigned input_named(const TomlView& t, const std::vector<std::string>& names, const std::string& name,
                     const toml::node* node) {
  const auto at = std::find(names.begin(), names.end(), name);
  if (at != names.end()) {
    if (std::count(names.begin(), names.end(), name) > 1)
      t.fail_at(node, "inputs",
                "\"" + name +
                    "\" is an input of more than one [[ensemble.perturbation]] (the same "
                    "target twice); a correlation cannot tell them apart");
    return static_cast<unsigned>(at - names.begin());
  }
  std::string listed;
  for (const auto& n : names) listed += " " + n;
  const std::vector<std::string_view> views(names.begin(), names.end());
  t.fail_at(node, "inputs",
            "\"" + name + "\" is not a sampled input; the inputs are:" + listed + did_you_mean(name, views));
}

sampling::InputCorrelation read_correlation(const TomlView& c, const EnsembleSpec& s) {
  c.check_keys({"inputs", "spearman", "normal_copula"});
  const std::vector<std::string> names = s.input_names();
  const auto inputs =
      string_list(c, "inputs", "two sampled inputs, e.g. [\"body.payload.mass\", \"body.cable.length\"]");
  if (inputs.size() != 2) c.fail("inputs", "give exactly two inputs (one [[ensemble.correlation]] per pair)");
  sampling::InputCorrelation r;
  r.a = input_named(c, names, inputs[0].first, inputs[0].second);
  r.b = input_named(c, names, inputs[1].first, inputs[1].second);
  if (r.a == r.b) c.fail("inputs", "the two inputs are the same");
  if (r.a > r.b) std::swap(r.a, r.b);
  const auto spearman = c.number("spearman");
  const auto copula = c.number("normal_copula");
  if (spearman.has_value() == copula.has_value())
    c.fail(spearman ? "normal_copula" : "inputs",
           "give one of spearman = r (rank correlation) or normal_copula = rho (the normal copula's parameter)");
  const char* key = spearman ? "spearman" : "normal_copula";
  const double value = spearman ? *spearman : *copula;
  if (!(value > -1.0 && value < 1.0)) c.fail(key, "must be in (-1, 1)");
  r.given_as_spearman = spearman.has_value();
  r.normal_copula = spearman ? sampling::normal_copula_of_spearman(value) : value;
  return r;
}

std::string describe(const sampling::InputCorrelation& c, const std::vector<std::string>& names) {
  return names[c.a] + " ~ " + names[c.b] + " (normal copula " + format_digits(c.normal_copula, 4) + ")";
}

// The normal copula's matrix must stay positive definite with entry `c`
// added: the smallest eigenvalue of its correlated inputs' part says (the
// rest is the identity).
void check_positive_definite(const TomlView& c, const EnsembleSpec& s) {
  const std::vector<std::string> names = s.input_names();
  std::vector<unsigned> inputs;
  for (const sampling::InputCorrelation& k : s.correlations) inputs.insert(inputs.end(), {k.a, k.b});
  std::sort(inputs.begin(), inputs.end());
  inputs.erase(std::unique(inputs.begin(), inputs.end()), inputs.end());
  auto at = [&inputs](unsigned d) {
    return static_cast<Eigen::Index>(std::lower_bound(inputs.begin(), inputs.end(), d) - inputs.begin());
  };
  const auto n = static_cast<Eigen::Index>(inputs.size());
  Eigen::MatrixXd r = Eigen::MatrixXd::Identity(n, n);
  for (const sampling::InputCorrelation& k : s.correlations)
    r(at(k.a), at(k.b)) = r(at(k.b), at(k.a)) = k.normal_copula;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(r, Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues().minCoeff();
  if (smallest > 1e-10) return;
  std::string listed;
  for (const sampling::InputCorrelation& k : s.correlations) listed += "\n  " + describe(k, names);
  c.fail("inputs",
         "with this one the correlations cannot hold together (their normal-copula matrix is not "
         "positive definite: smallest eigenvalue " +
             format_digits(smallest, 3) + "):" + listed + "\nweaken some of them");
}

}  // namespace

void read_correlations(const TomlView& t, EnsembleSpec& s) {
  const std::vector<TomlView> entries = t.table_array("correlation");
  if (entries.empty()) return;
  if (const std::string_view why = designs::rules_of(s.design).why_no_correlations(); !why.empty())
    entries.front().fail("inputs", std::string(why) +
                                       ". Use design = \"monte_carlo\", \"latin_hypercube\" or \"sobol\": the "
                                       "rank measures (Spearman, SRRC) in /sensitivity allow correlated inputs");
  for (const TomlView& c : entries) {
    s.correlations.push_back(read_correlation(c, s));
    const sampling::InputCorrelation& last = s.correlations.back();
    for (std::size_t k = 0; k + 1 < s.correlations.size(); ++k)
      if (s.correlations[k].a == last.a && s.correlations[k].b == last.b)
        c.fail("inputs", "this pair is already correlated by an earlier [[ensemble.correlation]]");
    check_positive_definite(c, s);
  }
}

}  // namespace treedyn
