// Saltelli's lines in the end-of-run summary: the Sobol' ranking, the
// blocks it rests on and the verdict on N.
#include <cmath>
#include <string>

#include "analysis/summary_text.hpp"
#include "designs/saltelli/saltelli_answer.hpp"

namespace treedyn::designs {

void SaltelliAnswer::print(std::ostream& out, const EnsembleSpec& spec, const Response&) const {
  const SobolIndices& s = indices;
  if (s.total.empty()) return;
  out << "    drivers (" << (spec.grouped ? "groups, " : "") << "total Sobol' index [95 %], from " << s.base_samples
      << " of " << blocks << " base points): ";
  analysis::print_ranking(out, spec.unit_names(), s.ranking, s.total, &s.total_ci, "base points");
  if (unreliable())
    out << "      unreliable: failed runs left " << s.base_samples << " of " << blocks
        << " base points complete; failures that depend on the inputs bias what remains\n";
  const IndexVerdict v = index_verdict(s);
  if (std::isfinite(v.widest))
    out << "      is N enough for the indices? " << (v.enough ? "yes" : "no")
        << ": the widest interval of a total index "
        << "that matters is " << analysis::number(v.widest, "%.2g") << " (" << spec.unit_names()[v.unit] << ")"
        << (v.enough ? ""
                     : "; about " + analysis::number(v.needed, "%.0f") + " base points would make it " +
                           analysis::number(kIndexIntervalWidth, "%.1f"))
        << "\n";
}

}  // namespace treedyn::designs
