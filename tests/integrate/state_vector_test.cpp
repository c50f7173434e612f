// treedyn's vector operations against N_VSerial's own, bit for bit: every
// operation, every special coefficient of a linear sum (the cases N_VSerial
// treats apart), every way the output may alias an input, and the fused
// operations against the generic fallback SUNDIALS uses without them.
#include "integrate/state_vector.hpp"

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <new>
#include <random>
#include <vector>

namespace treedyn::sundials {
namespace {

constexpr sunindextype kLength = 37;  // odd and past a vector register's width

class StateVector : public ::testing::Test {
 protected:
  // Twin vectors: one with N_VSerial's operations, one with treedyn's, the
  // same numbers in both.
  struct Twin {
    Vector serial, compiled;
  };

  Twin twin(double lowest = -3.0, double highest = 3.0) {
    Twin t{Vector(N_VNew_Serial(kLength, context_)), new_state_vector(kLength, context_)};
    std::uniform_real_distribution<double> u(lowest, highest);
    for (sunindextype i = 0; i < kLength; ++i) NV_Ith_S(t.serial.get(), i) = NV_Ith_S(t.compiled.get(), i) = u(rng_);
    return t;
  }

  static void expect_same_bits(N_Vector serial, N_Vector compiled, const char* what) {
    for (sunindextype i = 0; i < kLength; ++i)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(NV_Ith_S(serial, i)), std::bit_cast<std::uint64_t>(NV_Ith_S(compiled, i)))
          << what << ", element " << i;
  }
  static void expect_same_bits(double serial, double compiled, const char* what) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(serial), std::bit_cast<std::uint64_t>(compiled)) << what;
  }

  Context context_;
  std::mt19937_64 rng_{20261202};
};

TEST_F(StateVector, ClonesCarryTheOperations) {
  Vector v = new_state_vector(kLength, context_);
  Vector clone(N_VClone(v.get()));
  EXPECT_EQ(clone->ops->nvlinearsum, v->ops->nvlinearsum);
  EXPECT_EQ(N_VGetVectorID(clone.get()), SUNDIALS_NVEC_SERIAL);  // the dense solver accepts it
  EXPECT_NE(v->ops->nvlinearsum, Vector(N_VNew_Serial(kLength, context_))->ops->nvlinearsum);
}

// The data start on a cache line, in the vector, its clones (one by one
// and as an array) and their clones, each their own, of the vector's
// length, every element writable; N_VDestroy frees them (the sanitizer
// pass would see a wrong free). Length 0 too.
TEST_F(StateVector, DataStartOnACacheLineInTheVectorAndItsClones) {
  const auto line_aligned = [](N_Vector v) { return reinterpret_cast<std::uintptr_t>(NV_DATA_S(v)) % 64 == 0; };
  for (const sunindextype n : {sunindextype{0}, sunindextype{1}, sunindextype{7}, kLength, sunindextype{700}}) {
    Vector v = new_state_vector(n, context_);
    Vector clone(N_VClone(v.get()));
    Vector clone_of_clone(N_VClone(clone.get()));
    N_Vector* array = N_VCloneVectorArray(2, v.get());
    ASSERT_NE(array, nullptr);
    std::vector<N_Vector> all{v.get(), clone.get(), clone_of_clone.get(), array[0], array[1]};
    for (std::size_t k = 0; k < all.size(); ++k) {
      N_Vector w = all[k];
      EXPECT_TRUE(line_aligned(w)) << "length " << n << ", vector " << k;
      EXPECT_EQ(N_VGetLength(w), n);
      EXPECT_EQ(NV_OWN_DATA_S(w), SUNTRUE);
      for (std::size_t j = 0; j < k; ++j) EXPECT_NE(NV_DATA_S(w), NV_DATA_S(all[j])) << "shared data";
      N_VConst(static_cast<double>(k), w);  // every element writable
      if (n > 0) {
        EXPECT_EQ(NV_Ith_S(w, n - 1), static_cast<double>(k));
      }
    }
    N_VDestroyVectorArray(array, 2);
  }
}

// A length no memory holds (a model asked for more than the machine has)
// is std::bad_alloc, which a rank reports as out of memory (exit 6), not a
// vector without data. The sanitizers' allocator stops the process on such
// a request instead of returning null: skipped there. So is a SUNDIALS
// whose index is 32 bits (Debian 13's): every length it can name fits in
// memory a machine may have (2^31 values, 16 GiB), so none is sure to fail.
TEST_F(StateVector, ALengthNoMemoryHoldsIsBadAlloc) {
#ifdef TREEDYN_SANITIZED
  GTEST_SKIP() << "the sanitizers' allocator aborts on an impossible size";
#endif
  if (sizeof(sunindextype) < 8) GTEST_SKIP() << "sunindextype has " << 8 * sizeof(sunindextype) << " bits here";
  const sunindextype length = std::numeric_limits<sunindextype>::max() / 64;  // 2^57 values: 2^60 bytes
  EXPECT_THROW((void)new_state_vector(length, context_), std::bad_alloc);
}

TEST_F(StateVector, LinearSumMatchesEveryCaseAndAliasOfTheSerialVector) {
  const double special[] = {1.0, -1.0, 0.0, 0.37, -0.37, 2.5};
  for (double a : special)
    for (double b : special)
      for (int alias = 0; alias < 3; ++alias) {  // z separate, z is x, z is y
        Twin x = twin(), y = twin(), z = twin();
        auto out = [&](Twin& t) -> Twin& { return alias == 1 ? x : alias == 2 ? y : t; };
        N_VLinearSum(a, x.serial.get(), b, y.serial.get(), out(z).serial.get());
        N_VLinearSum(a, x.compiled.get(), b, y.compiled.get(), out(z).compiled.get());
        SCOPED_TRACE(testing::Message() << "a = " << a << ", b = " << b << ", alias " << alias);
        expect_same_bits(out(z).serial.get(), out(z).compiled.get(), "linear sum");
      }
}

TEST_F(StateVector, ElementwiseOperationsMatchTheSerialVector) {
  for (double c : {1.0, -1.0, 0.0, 0.37}) {
    Twin x = twin(), z = twin();
    N_VScale(c, x.serial.get(), z.serial.get());
    N_VScale(c, x.compiled.get(), z.compiled.get());
    expect_same_bits(z.serial.get(), z.compiled.get(), "scale");
    N_VScale(c, x.serial.get(), x.serial.get());
    N_VScale(c, x.compiled.get(), x.compiled.get());
    expect_same_bits(x.serial.get(), x.compiled.get(), "scale in place");
  }
  Twin x = twin(), y = twin(0.5, 2.0), z = twin();
  N_VProd(x.serial.get(), y.serial.get(), z.serial.get());
  N_VProd(x.compiled.get(), y.compiled.get(), z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "product");
  N_VDiv(x.serial.get(), y.serial.get(), z.serial.get());
  N_VDiv(x.compiled.get(), y.compiled.get(), z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "quotient");
  N_VAbs(x.serial.get(), z.serial.get());
  N_VAbs(x.compiled.get(), z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "absolute value");
  N_VInv(y.serial.get(), z.serial.get());
  N_VInv(y.compiled.get(), z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "inverse");
  N_VAddConst(x.serial.get(), 0.3, z.serial.get());
  N_VAddConst(x.compiled.get(), 0.3, z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "add constant");
  N_VCompare(1.0, x.serial.get(), z.serial.get());
  N_VCompare(1.0, x.compiled.get(), z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "compare");
  N_VConst(0.7, z.serial.get());
  N_VConst(0.7, z.compiled.get());
  expect_same_bits(z.serial.get(), z.compiled.get(), "constant");
}

TEST_F(StateVector, ReductionsMatchTheSerialVector) {
  Twin x = twin(), w = twin(0.0, 1e6), id = twin(-1.0, 1.0), d = twin();
  NV_Ith_S(d.serial.get(), 4) = NV_Ith_S(d.compiled.get(), 4) = 0.0;  // a zero for the tests that skip zeros
  expect_same_bits(N_VDotProd(x.serial.get(), w.serial.get()), N_VDotProd(x.compiled.get(), w.compiled.get()), "dot");
  expect_same_bits(N_VMaxNorm(x.serial.get()), N_VMaxNorm(x.compiled.get()), "max norm");
  expect_same_bits(N_VWrmsNorm(x.serial.get(), w.serial.get()), N_VWrmsNorm(x.compiled.get(), w.compiled.get()),
                   "WRMS norm");
  expect_same_bits(N_VWrmsNormMask(x.serial.get(), w.serial.get(), id.serial.get()),
                   N_VWrmsNormMask(x.compiled.get(), w.compiled.get(), id.compiled.get()), "masked WRMS norm");
  expect_same_bits(N_VWSqrSumLocal(x.serial.get(), w.serial.get()), N_VWSqrSumLocal(x.compiled.get(), w.compiled.get()),
                   "weighted square sum");
  expect_same_bits(N_VMin(x.serial.get()), N_VMin(x.compiled.get()), "minimum");
  expect_same_bits(N_VWL2Norm(x.serial.get(), w.serial.get()), N_VWL2Norm(x.compiled.get(), w.compiled.get()),
                   "weighted L2 norm");
  expect_same_bits(N_VL1Norm(x.serial.get()), N_VL1Norm(x.compiled.get()), "L1 norm");
  expect_same_bits(N_VMinQuotient(x.serial.get(), d.serial.get()), N_VMinQuotient(x.compiled.get(), d.compiled.get()),
                   "minimum quotient");
  Twin inv = twin();
  EXPECT_EQ(N_VInvTest(d.serial.get(), inv.serial.get()), N_VInvTest(d.compiled.get(), inv.compiled.get()));
  expect_same_bits(inv.serial.get(), inv.compiled.get(), "inverse test");
  Twin constraints = twin(-2.0, 2.0), mask = twin();
  for (sunindextype i = 0; i < kLength; i += 5)
    NV_Ith_S(constraints.serial.get(), i) = NV_Ith_S(constraints.compiled.get(), i) = 0.0;
  EXPECT_EQ(N_VConstrMask(constraints.serial.get(), x.serial.get(), mask.serial.get()),
            N_VConstrMask(constraints.compiled.get(), x.compiled.get(), mask.compiled.get()));
  expect_same_bits(mask.serial.get(), mask.compiled.get(), "constraint mask");
}

// The fused operations give what CVODE and ARKODE got before, through the
// generic fallback of a serial vector without fused operations.
TEST_F(StateVector, FusedOperationsMatchTheGenericFallback) {
  for (int count : {1, 2, 3, 6}) {
    std::vector<Twin> X;
    for (int k = 0; k < count; ++k) X.push_back(twin());
    std::vector<double> c{0.37, 0.37, -1.0, 1.0, 2.5, -0.37};
    for (int alias = 0; alias < 2; ++alias) {  // z separate, z is X[0]
      Twin z = twin();
      std::vector<N_Vector> serial, compiled;
      for (auto& t : X) serial.push_back(t.serial.get()), compiled.push_back(t.compiled.get());
      N_Vector zs = alias == 1 ? serial[0] : z.serial.get(), zc = alias == 1 ? compiled[0] : z.compiled.get();
      ASSERT_EQ(N_VLinearCombination(count, c.data(), serial.data(), zs), 0);
      ASSERT_EQ(N_VLinearCombination(count, c.data(), compiled.data(), zc), 0);
      SCOPED_TRACE(testing::Message() << count << " vectors, alias " << alias);
      expect_same_bits(zs, zc, "linear combination");
    }
    Twin x = twin();
    std::vector<Twin> Y, Z;
    for (int k = 0; k < count; ++k) Y.push_back(twin()), Z.push_back(twin());
    std::vector<N_Vector> ys, yc, zs, zc;
    for (int k = 0; k < count; ++k) {
      ys.push_back(Y[k].serial.get()), yc.push_back(Y[k].compiled.get());
      zs.push_back(Z[k].serial.get()), zc.push_back(Z[k].compiled.get());
    }
    ASSERT_EQ(N_VScaleAddMulti(count, c.data(), x.serial.get(), ys.data(), zs.data()), 0);
    ASSERT_EQ(N_VScaleAddMulti(count, c.data(), x.compiled.get(), yc.data(), zc.data()), 0);
    for (int k = 0; k < count; ++k) expect_same_bits(zs[k], zc[k], "scale-add-multi");
    ASSERT_EQ(N_VScaleAddMulti(count, c.data(), x.serial.get(), ys.data(), ys.data()), 0);
    ASSERT_EQ(N_VScaleAddMulti(count, c.data(), x.compiled.get(), yc.data(), yc.data()), 0);
    for (int k = 0; k < count; ++k) expect_same_bits(ys[k], yc[k], "scale-add-multi in place");
    std::vector<double> ds(count), dc(count);
    ASSERT_EQ(N_VDotProdMulti(count, x.serial.get(), ys.data(), ds.data()), 0);
    ASSERT_EQ(N_VDotProdMulti(count, x.compiled.get(), yc.data(), dc.data()), 0);
    for (int k = 0; k < count; ++k) expect_same_bits(ds[k], dc[k], "dot products");
  }
}

}  // namespace
}  // namespace treedyn::sundials
