#include "persistence/record_codec.hpp"

namespace treedyn::persistence {

void write_record(const SampleRecord& r, ByteWriter& out) {
  out.put(r.index);
  out.put(r.status);
  out.put(r.time_reached);
  for (const IntegratorStatField& f : kIntegratorStatFields) out.put(r.stats.*f.member);
  out.put_text(r.reason);
  for (const auto* v : {&r.inputs, &r.reductions, &r.responses, &r.final_state, &r.trajectory}) out.put_vector(*v);
}

SampleRecord read_record(ByteReader& in) {
  SampleRecord r;
  read_record_into(in, r);
  return r;
}

void read_record_into(ByteReader& in, SampleRecord& r) {
  r.index = in.get<std::uint64_t>();
  r.status = in.get<SampleStatus>();
  if (static_cast<std::int32_t>(r.status) < 0 || r.status > SampleStatus::not_run)
    in.fail("a sample record with an unknown status");
  r.time_reached = in.get<double>();
  for (const IntegratorStatField& f : kIntegratorStatFields) r.stats.*f.member = in.get<long>();
  in.get_text_into(r.reason);
  for (auto* v : {&r.inputs, &r.reductions, &r.responses, &r.final_state, &r.trajectory}) in.get_vector_into(*v);
}

std::size_t encoded_size(const SampleRecord& r) {
  std::size_t doubles = 0;
  for (const auto* v : {&r.inputs, &r.reductions, &r.responses, &r.final_state, &r.trajectory}) doubles += v->size();
  return sizeof r.index + sizeof r.status + sizeof r.time_reached + kIntegratorStatFields.size() * sizeof(long) +
         sizeof(std::uint64_t) + r.reason.size() + 5 * sizeof(std::uint64_t) + doubles * sizeof(double);
}

std::size_t least_encoded_size() { return encoded_size(SampleRecord{}); }

void append_record(const SampleRecord& record, std::vector<char>& buffer) {
  ByteWriter out(buffer);
  write_record(record, out);
}

std::vector<SampleRecord> read_records(std::span<const char> buffer, const std::string& what) {
  std::vector<SampleRecord> records;
  ByteReader in(buffer, what);
  while (!in.done()) records.push_back(read_record(in));
  return records;
}

}  // namespace treedyn::persistence
