// `treedyn-ensemble merge -o OUT.h5 PART ...`: the parts of a split ensemble
// (--samples FIRST:END) into one ensemble file, bitwise identical in /stats
// and /samples to one run over the union (the statistics are exact integer
// sums, and every part used the same calibration). Serial: no MPI.
#pragma once

#include <string>
#include <vector>

#include "hdf5/provenance.hpp"

namespace treedyn {

// Returns the exit code: 2 for parts of another job or build, damaged parts,
// or overlapping ranges; 4 when the output cannot be written. An incomplete
// set merges with a note; the file says which samples it holds.
int merge_parts(const std::vector<std::string>& parts, const std::string& output_path, bool quiet,
                const h5::RunProvenance& run);

}  // namespace treedyn
