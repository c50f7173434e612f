#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/answers.hpp"

namespace treedyn::ensemble {
namespace {

std::string number(double v, const char* format = "%.6g") {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// The inputs that matter most: by total Sobol' index (saltelli), else by
// |Spearman|; at most three.
void print_drivers(std::ostream& out, const EnsembleSpec& spec, const ResponseAnswer& a) {
  const std::vector<std::string> names = spec.input_names();
  const bool sobol = a.sobol.has_value();
  const std::vector<double>& measure = sobol ? a.sobol->total : a.ranks.spearman;
  if (measure.size() != names.size() || names.empty()) return;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < names.size(); ++i)
    if (std::isfinite(measure[i])) order.push_back(i);
  if (order.empty()) return;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return std::abs(measure[x]) > std::abs(measure[y]);
  });
  out << "    drivers (" << (sobol ? "total Sobol' index" : "Spearman rank correlation") << "):";
  for (std::size_t k = 0; k < std::min<std::size_t>(order.size(), 3); ++k)
    out << (k ? "," : "") << " " << names[order[k]] << " " << number(measure[order[k]], "%.3g");
  out << "\n";
}

}  // namespace

void print_response_summary(std::ostream& out, const EnsembleSpec& spec,
                            const std::vector<ResponseAnswer>& answers) {
  if (answers.empty()) return;
  out << "responses: mean +- standard error (successful samples with finite values"
      << (spec.design == Design::saltelli ? "; saltelli: the A and B runs" : "") << ")\n";
  for (std::size_t r = 0; r < answers.size(); ++r) {
    const Response& response = spec.responses[r];
    const ResponseAnswer& a = answers[r];
    std::string what = std::string(name(response.reduce)) + " of " + response.quantity + " " + response.column;
    if (response.reduce == Response::Reduce::at_time) what += " at t = " + number(response.time) + " s";
    if (response.reduce == Response::Reduce::first_time_above || response.reduce == Response::Reduce::first_time_below)
      what += " " + number(response.threshold);
    out << "  " << response.name << " (" << what << "): " << number(a.mean) << " +- "
        << number(a.sem, "%.3g") << " " << response.units << "  [" << a.used << " used";
    if (a.not_finite > 0) out << ", " << a.not_finite << " never crossed (+inf)";
    if (a.failed > 0) out << ", " << a.failed << " failed";
    out << "]\n";
    if (const auto& e = a.exceedance) {
      out << "    P(" << response.name << (response.fail_if == Response::FailIf::above ? " > " : " < ")
          << number(response.limit) << " " << response.units << ") = " << number(e->probability, "%.4g")
          << " (" << e->exceeded << " of " << e->successful << "), 95 % Wilson interval ["
          << number(e->interval.low, "%.4g") << ", " << number(e->interval.high, "%.4g") << "]";
      if (e->failed > 0) out << "; " << e->failed << " failed samples not in the count";
      out << "\n";
    }
    print_drivers(out, spec, a);
  }
}

}  // namespace treedyn::ensemble
