// RAII owners for the SUNDIALS objects treedyn uses. Each deleter is the
// matching SUNDIALS destroy call; nothing is freed twice or leaked.
#pragma once

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace treedyn::sundials {

// Thrown only while setting an integrator up (never inside a SUNDIALS callback).
class SetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws SetupError naming the call when a SUNDIALS set-up call fails.
inline void check(int flag, const char* call) {
  if (flag < 0) throw SetupError(std::string("SUNDIALS call ") + call + " failed with flag " + std::to_string(flag));
}
// The same for a call named in two parts ("CVODE", " dense output"),
// joined only when it failed: a check at every output time or in every
// sample's set-up allocates nothing.
inline void check(int flag, std::string_view package, std::string_view call) {
  if (flag < 0) check(flag, (std::string(package) + std::string(call)).c_str());
}
template <class T>
T* check_created(T* p, const char* call) {
  if (p == nullptr) throw SetupError(std::string("SUNDIALS call ") + call + " returned null");
  return p;
}

class Context {
 public:
  // No communicator: SUNDIALS 7 (built with MPI in Debian 13) takes
  // SUN_COMM_NULL, where 6 took a null pointer.
#if SUNDIALS_VERSION_MAJOR >= 7
  Context() { check(SUNContext_Create(SUN_COMM_NULL, &ctx_), "SUNContext_Create"); }
#else
  Context() { check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create"); }
#endif
  ~Context() { SUNContext_Free(&ctx_); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  operator SUNContext() const { return ctx_; }

 private:
  SUNContext ctx_ = nullptr;
};

struct VectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
};
struct LinearSolverDeleter {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
struct NonlinearSolverDeleter {
  void operator()(SUNNonlinearSolver s) const { SUNNonlinSolFree(s); }
};
struct CvodeDeleter {
  void operator()(void* mem) const { CVodeFree(&mem); }
};
struct ErkDeleter {
#if SUNDIALS_VERSION_MAJOR >= 7
  void operator()(void* mem) const { ARKodeFree(&mem); }
#else
  void operator()(void* mem) const { ERKStepFree(&mem); }
#endif
};

using Vector = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using Matrix = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
using LinearSolver = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;
using NonlinearSolver = std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinearSolverDeleter>;
using CvodeMemory = std::unique_ptr<void, CvodeDeleter>;
using ErkMemory = std::unique_ptr<void, ErkDeleter>;

}  // namespace treedyn::sundials
