// Removes a temporary file when the process is ended by a signal (SIGTERM
// from a batch system's time limit or from MPI_Abort, SIGINT from Ctrl-C,
// SIGHUP), where no destructor runs. One guarded file per process at a time.
#pragma once

#include <filesystem>

namespace treedyn::h5 {

class RemoveOnSignal {
 public:
  explicit RemoveOnSignal(const std::filesystem::path& path);
  ~RemoveOnSignal();  // stops guarding (the owner removes or renames the file)
  RemoveOnSignal(const RemoveOnSignal&) = delete;
  RemoveOnSignal& operator=(const RemoveOnSignal&) = delete;
};

}  // namespace treedyn::h5
