// `treedyn report FILE.h5 [-o DIR] [--quantity Q ...]`: checks the file,
// prints its text summary (for an ensemble, the same code as the end of
// treedyn-ensemble), writes it to DIR/summary.txt, and starts the plotting
// script (src/report/treedyn_report.py, Debian's python3-h5py and
// python3-matplotlib) that writes DIR/index.html and its PNG figures.
#pragma once

#include <string>
#include <vector>

namespace treedyn {

// Returns the exit code; errors are one line on stderr.
int report_command(const std::string& file, std::string out_dir, const std::vector<std::string>& quantities);

}  // namespace treedyn
