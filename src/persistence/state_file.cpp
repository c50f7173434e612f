#include "persistence/state_file.hpp"

namespace treedyn::persistence {
namespace {

constexpr std::uint64_t kMagic = 0x3230545043445454ull;  // "TTDCPT02"
constexpr std::size_t kFlushBytes = std::size_t{4} << 20;

}  // namespace

RunIdentity run_identity(const std::string& job_text, const std::string& build) {
  return {hex64(hash64(job_text)), build};
}

StateFileWriter::StateFileWriter(const std::filesystem::path& path, StateKind kind, const RunIdentity& id)
    : file_(path) {
  out_.put(kMagic);
  out_.put(kind);
  out_.put_text(id.job_hash);
  out_.put_text(id.build);
}

void StateFileWriter::flush() {
  hash_.update(buffer_);
  file_.write(buffer_);
  buffer_.clear();
}

void StateFileWriter::flush_if_large() {
  if (buffer_.size() >= kFlushBytes) flush();
}

void StateFileWriter::put_large(std::span<const char> bytes) {
  out_.put(static_cast<std::uint64_t>(bytes.size()));
  flush();
  hash_.update(bytes);
  file_.write(bytes);
}

void StateFileWriter::commit(process::AtomicFile::Sync sync) {
  flush();
  const std::uint64_t digest = hash_.digest();
  file_.write({reinterpret_cast<const char*>(&digest), sizeof digest});
  file_.commit(sync);
}

ByteReader open_state_file(const std::vector<char>& bytes, StateKind kind, const std::filesystem::path& path,
                           const RunIdentity* expected, RunIdentity* found) {
  const std::string what = path.string();
  std::uint64_t magic = 0;
  if (bytes.size() >= sizeof magic) std::memcpy(&magic, bytes.data(), sizeof magic);
  if (bytes.size() < sizeof magic + sizeof(std::uint64_t) || magic != kMagic)
    throw CheckpointError(what + " is not a treedyn checkpoint or part file (or one of another layout)");
  const std::span<const char> body(bytes.data(), bytes.size() - sizeof(std::uint64_t));
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + body.size(), sizeof stored);
  ByteReader in(body, what);
  try {
    if (hash64(body) != stored) in.fail("its hash does not match its content");
    in.get<std::uint64_t>();
    if (in.get<StateKind>() != kind) in.fail("another kind of file than expected here");
    const RunIdentity id{in.get_text(), in.get_text()};
    if (found) *found = id;
    if (!expected) return in;
    if (id.job_hash != expected->job_hash)
      throw CheckpointError(what + " belongs to another job file (job text hash " + id.job_hash + ", this job's is " +
                            expected->job_hash +
                            "): resume with the job file it was started with, or remove the checkpoint");
    if (id.build != expected->build)
      throw CheckpointError(what + " was written by another build (" + id.build + "; this is " + expected->build +
                            "): resume with that build, or remove the checkpoint");
  } catch (const DecodeError& e) {
    refuse_damaged(e);
  }
  return in;
}

void refuse_damaged(const DecodeError& e) { throw CheckpointError(e.what()); }

}  // namespace treedyn::persistence
