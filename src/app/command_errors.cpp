#include "app/command_errors.hpp"

#include <iostream>
#include <new>

#include "common/exit_codes.hpp"
#include "job/job_error.hpp"
#include "process/atomic_file.hpp"

namespace treedyn {

int exit_code_of(const std::function<int()>& command) {
  try {
    return command();
  } catch (const JobError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const CommandRefused& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const process::FileError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory: the job asks for more than this machine (or its memory limit) gives\n";
    return kExitMemory;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return kExitInternal;
  }
}

}  // namespace treedyn
