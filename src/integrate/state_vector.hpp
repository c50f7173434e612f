// The integrator's state vector: SUNDIALS' serial N_Vector (its content
// and ID, so the dense linear solver still accepts it) with its arithmetic
// operations replaced by treedyn's own, compiled with the project's
// optimisation, and its data on whole cache lines of their own (the
// vector's and every clone's: 64-byte aligned, owned, freed by
// N_VDestroy_Serial).
//
// Why: Debian 12's and 13's libsundials are built without optimisation
// (-O0: every loop index lives in memory), and the serial vector's
// operations are then most of an integration (BENCHMARKS.md, "Samples per
// second"). The
// replacements compute what N_VSerial computes, operation by operation,
// in the same order and with the same special cases (a == b in a linear
// sum is a * (x + y), not a * x + b * y), and the fused operations do what
// SUNDIALS' generic fallback does without them. So the integration gives
// the same bits as with N_VSerial (tests/integrate/state_vector_test.cpp).
// Clones copy the operations: every vector CVODE or ARKODE makes from this
// one uses them.
#pragma once

#include "integrate/sundials_handles.hpp"

namespace treedyn::sundials {

// A serial vector of `length` numbers with treedyn's operations.
Vector new_state_vector(sunindextype length, SUNContext context);

// Replaces the arithmetic operations and the clone of an existing serial
// vector `v` (its own data stay as they are; its clones get aligned data).
// Exposed for the test that compares them with N_VSerial's own.
void use_compiled_operations(N_Vector v);

}  // namespace treedyn::sundials
