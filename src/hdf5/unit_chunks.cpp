#include "hdf5/unit_chunks.hpp"

#include "common/bytes.hpp"
#include "hdf5/deflate.hpp"
#include "hdf5/hdf5.hpp"
#include "hdf5/row_dataset.hpp"
#include "persistence/record_codec.hpp"

namespace treedyn::h5 {

void UnitEncoder::encode(std::span<SampleRecord> run, std::vector<char>& out) {
  ByteWriter w(out);
  w.put(static_cast<std::uint64_t>(run.empty() ? 0 : run.front().index));
  w.put(static_cast<std::uint64_t>(run.size()));
  w.put(static_cast<std::uint64_t>(rows_.datasets().size()));
  for (std::size_t i = 0; i < rows_.datasets().size(); ++i) {
    raw_.clear();
    rows_.append(i, run, raw_);
    deflate(raw_, kRowsDeflateLevel, stream_);
    const bool deflated =
        static_cast<double>(stream_.size()) < (1.0 - RowDataset::kWorthShrinking) * static_cast<double>(raw_.size());
    const std::vector<unsigned char>& stored = deflated ? stream_ : raw_;
    w.put(static_cast<std::uint8_t>(deflated ? 1 : 0));
    w.put(static_cast<std::uint64_t>(stored.size()));
    w.put_bytes(std::span<const char>(reinterpret_cast<const char*>(stored.data()), stored.size()));
  }
  for (SampleRecord& r : run) {
    r.reductions.clear();
    r.final_state.clear();
    r.trajectory.clear();
    persistence::write_record(r, w);
  }
}

Unit decode_unit(std::span<const char> message, std::size_t datasets, const std::string& what) {
  Unit unit;
  decode_unit_into(message, datasets, what, unit);
  return unit;
}

void decode_unit_into(std::span<const char> message, std::size_t datasets, const std::string& what, Unit& unit) {
  ByteReader in(message, what);
  unit.first = in.get<std::uint64_t>();
  unit.rows = in.get<std::uint64_t>();
  if (in.get<std::uint64_t>() != datasets) in.fail("a unit of another number of datasets");
  unit.chunks.resize(datasets);
  for (UnitChunk& c : unit.chunks) {
    c.deflated = in.get<std::uint8_t>() != 0;
    const std::span<const char> bytes = in.get_bytes(in.get<std::uint64_t>());
    c.bytes = std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  }
  // Checked before sizing the records by it: a damaged count would
  // otherwise ask for any amount of memory.
  if (unit.rows > in.left() / persistence::least_encoded_size()) in.fail("a unit whose records are not its rows");
  unit.records.resize(unit.rows);
  for (std::size_t k = 0; k < unit.records.size(); ++k) {
    persistence::read_record_into(in, unit.records[k]);
    if (unit.records[k].index != unit.first + k) in.fail("a unit's records out of order");
  }
  if (!in.done()) in.fail("a unit whose records are not its rows");
}

}  // namespace treedyn::h5
