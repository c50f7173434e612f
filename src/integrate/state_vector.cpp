#include "integrate/state_vector.hpp"

#include <nvector/nvector_serial.h>

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <new>
#include <span>

// Every operation below states the N_VSerial expression it reproduces.
// Products by +-1 are exact, and IEEE addition is commutative with
// symmetric rounding (so y - x == -(x - y) and -y - x == -(x + y) exactly):
// that is what lets one expression stand for several of N_VSerial's cases.
namespace treedyn::sundials {
namespace {

std::span<double> data(N_Vector v) { return {NV_DATA_S(v), static_cast<std::size_t>(NV_LENGTH_S(v))}; }

// N_VLinearSum_Serial: a == b is a (x + y) and a == -b is a (x - y) (its
// VScaleSum and VScaleDiff); every other case, the axpy ones included, is
// a x + b y rounded once per product and once for the sum.
void linear_sum(sunrealtype a, N_Vector x, sunrealtype b, N_Vector y, N_Vector z) {
  const auto xd = data(x), yd = data(y), zd = data(z);
  const std::size_t n = zd.size();
  if (a == b)
    for (std::size_t i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
  else if (a == -b)
    for (std::size_t i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
  else
    for (std::size_t i = 0; i < n; ++i) zd[i] = a * xd[i] + b * yd[i];
}

void constant(sunrealtype c, N_Vector z) {
  for (double& v : data(z)) v = c;
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  const auto xd = data(x), yd = data(y), zd = data(z);
  for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = xd[i] * yd[i];
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  const auto xd = data(x), yd = data(y), zd = data(z);
  for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = xd[i] / yd[i];
}

// N_VScale_Serial: copy for c = 1, negation for c = -1 (only a NaN's sign
// would tell them from c x), c x otherwise.
void scale(sunrealtype c, N_Vector x, N_Vector z) {
  const auto xd = data(x), zd = data(z);
  if (c == 1.0)
    for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = xd[i];
  else if (c == -1.0)
    for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = -xd[i];
  else
    for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = c * xd[i];
}

void absolute(N_Vector x, N_Vector z) {
  const auto xd = data(x), zd = data(z);
  for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = std::fabs(xd[i]);
}

void inverse(N_Vector x, N_Vector z) {
  const auto xd = data(x), zd = data(z);
  for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = 1.0 / xd[i];
}

void add_constant(N_Vector x, sunrealtype b, N_Vector z) {
  const auto xd = data(x), zd = data(z);
  for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = xd[i] + b;
}

// The reductions sum in index order, as N_VSerial does.
sunrealtype dot(N_Vector x, N_Vector y) {
  const auto xd = data(x), yd = data(y);
  double sum = 0.0;
  for (std::size_t i = 0; i < xd.size(); ++i) sum += xd[i] * yd[i];
  return sum;
}

sunrealtype max_norm(N_Vector x) {
  double max = 0.0;
  for (double v : data(x))
    if (std::fabs(v) > max) max = std::fabs(v);
  return max;
}

sunrealtype weighted_square_sum(N_Vector x, N_Vector w) {
  const auto xd = data(x), wd = data(w);
  double sum = 0.0;
  for (std::size_t i = 0; i < xd.size(); ++i) {
    const double p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

sunrealtype weighted_square_sum_masked(N_Vector x, N_Vector w, N_Vector id) {
  const auto xd = data(x), wd = data(w), idd = data(id);
  double sum = 0.0;
  for (std::size_t i = 0; i < xd.size(); ++i)
    if (idd[i] > 0.0) {
      const double p = xd[i] * wd[i];
      sum += p * p;
    }
  return sum;
}

// SUNRsqrt: 0 for a non-positive argument.
double root(double v) { return v <= 0.0 ? 0.0 : std::sqrt(v); }

sunrealtype wrms_norm(N_Vector x, N_Vector w) {
  return root(weighted_square_sum(x, w) / static_cast<double>(NV_LENGTH_S(x)));
}

sunrealtype wrms_norm_masked(N_Vector x, N_Vector w, N_Vector id) {
  return root(weighted_square_sum_masked(x, w, id) / static_cast<double>(NV_LENGTH_S(x)));
}

sunrealtype minimum(N_Vector x) {
  const auto xd = data(x);
  double min = xd[0];
  for (std::size_t i = 1; i < xd.size(); ++i)
    if (xd[i] < min) min = xd[i];
  return min;
}

sunrealtype weighted_l2_norm(N_Vector x, N_Vector w) { return root(weighted_square_sum(x, w)); }

sunrealtype l1_norm(N_Vector x) {
  double sum = 0.0;
  for (double v : data(x)) sum += std::fabs(v);
  return sum;
}

void compare(sunrealtype c, N_Vector x, N_Vector z) {
  const auto xd = data(x), zd = data(z);
  for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = std::fabs(xd[i]) >= c ? 1.0 : 0.0;
}

sunbooleantype inverse_test(N_Vector x, N_Vector z) {
  const auto xd = data(x), zd = data(z);
  sunbooleantype no_zero = SUNTRUE;
  for (std::size_t i = 0; i < xd.size(); ++i) {
    if (xd[i] == 0.0)
      no_zero = SUNFALSE;
    else
      zd[i] = 1.0 / xd[i];
  }
  return no_zero;
}

sunbooleantype constraint_mask(N_Vector c, N_Vector x, N_Vector m) {
  const auto cd = data(c), xd = data(x), md = data(m);
  bool violated = false;
  for (std::size_t i = 0; i < xd.size(); ++i) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    if ((std::fabs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0.0) || (std::fabs(cd[i]) > 0.5 && xd[i] * cd[i] < 0.0)) {
      md[i] = 1.0;
      violated = true;
    }
  }
  return violated ? SUNFALSE : SUNTRUE;
}

sunrealtype min_quotient(N_Vector num, N_Vector denom) {
  const auto nd = data(num), dd = data(denom);
  bool first = true;
  double min = DBL_MAX;  // SUN_BIG_REAL
  for (std::size_t i = 0; i < nd.size(); ++i) {
    if (dd[i] == 0.0) continue;
    const double q = nd[i] / dd[i];
    min = first ? q : (min < q ? min : q);  // SUNMIN(min, q), ties to q as there
    first = false;
  }
  return min;
}

// The fused operations as SUNDIALS' generic fallback composes them when a
// vector has none: z = c0 X0, then z += ci Xi one vector at a time (so an
// Xi that is z reads the partial sum, as there).
int linear_combination(int count, sunrealtype* c, N_Vector* X, N_Vector z) {
  const auto zd = data(z);
  scale(c[0], X[0], z);
  for (int k = 1; k < count; ++k) {
    const auto xd = data(X[k]);
    for (std::size_t i = 0; i < zd.size(); ++i) zd[i] = c[k] * xd[i] + zd[i];
  }
  return 0;
}

// Zi = ai x + Yi, one vector at a time (the fallback's linear sums with b = 1).
int scale_add_multi(int count, sunrealtype* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  for (int k = 0; k < count; ++k) linear_sum(a[k], x, 1.0, Y[k], Z[k]);
  return 0;
}

int dot_multi(int count, N_Vector x, N_Vector* Y, sunrealtype* dots) {
  for (int k = 0; k < count; ++k) dots[k] = dot(x, Y[k]);
  return 0;
}

sunindextype length(N_Vector v) { return NV_LENGTH_S(v); }
sunrealtype* array(N_Vector v) { return NV_DATA_S(v); }

// The data of an empty N_VSerial `v` on whole cache lines of their own,
// owned by `v` (N_VDestroy_Serial frees them). The operations above run
// over 7 to 700 values; where malloc happened to put them (16 bytes
// aligned, anywhere in a line) moved a build's speed (BENCHMARKS.md, "No
// allocation per output time"). False when out of memory.
bool own_aligned_data(N_Vector v) {
  const std::size_t bytes = (static_cast<std::size_t>(NV_LENGTH_S(v)) * sizeof(sunrealtype) + 63) / 64 * 64;
  void* p = std::aligned_alloc(64, bytes == 0 ? 64 : bytes);
  if (p == nullptr) return false;
  NV_DATA_S(v) = static_cast<sunrealtype*>(p);
  NV_OWN_DATA_S(v) = SUNTRUE;
  return true;
}

// N_VClone_Serial, with the data aligned as above. The clone has `w`'s
// operations, this one included.
N_Vector clone(N_Vector w) {
  N_Vector v = N_VCloneEmpty_Serial(w);
  if (v != nullptr && !own_aligned_data(v)) {
    N_VDestroy_Serial(v);
    return nullptr;
  }
  return v;
}

}  // namespace

void use_compiled_operations(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvclone = clone;
  ops->nvgetlength = length;
  ops->nvgetarraypointer = array;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvprod = product;
  ops->nvdiv = quotient;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvinv = inverse;
  ops->nvaddconst = add_constant;
  ops->nvdotprod = dot;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvwrmsnormmask = wrms_norm_masked;
  ops->nvmin = minimum;
  ops->nvwl2norm = weighted_l2_norm;
  ops->nvl1norm = l1_norm;
  ops->nvcompare = compare;
  ops->nvinvtest = inverse_test;
  ops->nvconstrmask = constraint_mask;
  ops->nvminquotient = min_quotient;
  ops->nvlinearcombination = linear_combination;
  ops->nvscaleaddmulti = scale_add_multi;
  ops->nvdotprodmulti = dot_multi;
  // The local reductions are the whole reductions on one process.
  ops->nvdotprodlocal = dot;
  ops->nvmaxnormlocal = max_norm;
  ops->nvminlocal = minimum;
  ops->nvl1normlocal = l1_norm;
  ops->nvinvtestlocal = inverse_test;
  ops->nvconstrmasklocal = constraint_mask;
  ops->nvminquotientlocal = min_quotient;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvwsqrsummasklocal = weighted_square_sum_masked;
}

Vector new_state_vector(sunindextype length, SUNContext context) {
  Vector v(check_created(N_VNewEmpty_Serial(length, context), "N_VNewEmpty_Serial"));
  if (!own_aligned_data(v.get())) throw std::bad_alloc();
  use_compiled_operations(v.get());
  return v;
}

}  // namespace treedyn::sundials
