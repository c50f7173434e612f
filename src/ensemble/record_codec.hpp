// Serialisation of per-sample records for the trip to the writer rank.
#pragma once

#include <vector>

#include "ensemble/sample_runner.hpp"

namespace treedyn::ensemble {

void append_record(const ensemble::SampleRecord& record, std::vector<char>& buffer);
// Reads all records of a buffer written by append_record.
std::vector<ensemble::SampleRecord> read_records(const std::vector<char>& buffer);

}  // namespace treedyn::ensemble
