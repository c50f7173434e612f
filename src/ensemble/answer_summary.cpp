#include <cmath>
#include <cstdio>
#include <string>

#include "ensemble/answers.hpp"

namespace treedyn::ensemble {
namespace {

std::string number(double v, const char* format = "%.6g") {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
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
  }
}

}  // namespace treedyn::ensemble
