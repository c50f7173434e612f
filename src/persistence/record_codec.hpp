// Per-sample records as bytes (common/bytes.hpp): the trip to the writer
// rank, the checkpoint's records files and the part files.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "output/sample_record.hpp"

namespace treedyn::persistence {

void write_record(const SampleRecord& record, ByteWriter& out);
SampleRecord read_record(ByteReader& in);
// Into `record`, reusing its vectors' capacity (no allocation per record
// once they have grown).
void read_record_into(ByteReader& in, SampleRecord& record);
// The fewest bytes write_record makes of any record.
std::size_t least_encoded_size();

// The bytes write_record makes of `record`, without making them.
std::size_t encoded_size(const SampleRecord& record);

// A buffer of records one after the other.
void append_record(const SampleRecord& record, std::vector<char>& buffer);
// Every record of such a buffer; throws DecodeError naming `what`.
std::vector<SampleRecord> read_records(std::span<const char> buffer, const std::string& what);

}  // namespace treedyn::persistence
