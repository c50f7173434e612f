// The writer a design's answers go through (hdf5/answer_group_writer.hpp),
// read back through the HDF5 C API as h5py and MATLAB read it: each kind of
// value keeps its type (a count an unsigned 64-bit scalar, a run's level a
// 32-bit integer, a chain a 64-bit one), its units and description, and a
// group made without a description has none (subset simulation's
// /rare_event/<response>, as before the writer).
#include "hdf5/answer_group_writer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

#include "support/command.hpp"
#include "support/hdf5_reader.hpp"

namespace treedyn {
namespace {

using testing::H5File;
using testing::has_attribute;
using testing::read_double_attribute;
using testing::read_doubles;
using testing::read_integer_attribute;
using testing::read_integers;
using testing::read_raw;
using testing::read_single_string_attribute;

class AnswerGroupWriter : public ::testing::Test {
 protected:
  std::filesystem::path write(void (*what)(designs::AnswerWriter&)) {
    const std::filesystem::path path = dir_.path() / "answers.h5";
    h5::File file(path);
    {
      h5::GroupAnswerWriter root(file.id());
      what(root);
    }
    file.commit();
    return path;
  }
  testing::TempDir dir_{"answer_group_writer"};
};

TEST_F(AnswerGroupWriter, EachKindKeepsItsTypeUnitsAndDescription) {
  const auto path = write([](designs::AnswerWriter& root) {
    const auto g = root.group("answer", "what it is");
    g->value("probability", 1.25e-6, "1", "P");
    g->count("runs", std::uint64_t{1} << 40, "runs made");
    g->pair("interval", 0.5, 0.75, "95 %");
    g->column("level", std::vector<std::int32_t>{0, 0, 1, 2}, "level of the run");
    g->column("chain", std::vector<std::int64_t>{0, 1, std::int64_t{1} << 40}, "chain of the run");
    g->array("thresholds", {1.0, 2.0, 3.0}, {3}, "N", "per level", {});
    const auto inner = g->group("undescribed", "");
    inner->attribute("limit", 2.5);
    inner->attribute("samples_per_level", 100LL);
  });
  H5File f(path);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(read_doubles(f.id(), "/answer/probability"), std::vector<double>{1.25e-6});
  const testing::RawDataset runs = read_raw(f.id(), "/answer/runs");
  EXPECT_EQ(runs.type_class, H5T_INTEGER);
  EXPECT_EQ(runs.type_size, 8u);
  EXPECT_EQ(runs.sign, H5T_SGN_NONE);
  EXPECT_TRUE(runs.dims.empty()) << "a scalar";
  EXPECT_EQ(read_integers(f.id(), "/answer/runs"), std::vector<long long>{1LL << 40});
  EXPECT_EQ(read_doubles(f.id(), "/answer/interval"), (std::vector<double>{0.5, 0.75}));
  const testing::RawDataset level = read_raw(f.id(), "/answer/level");
  EXPECT_EQ(level.type_class, H5T_INTEGER);
  EXPECT_EQ(level.type_size, 4u);
  EXPECT_EQ(level.sign, H5T_SGN_2);
  EXPECT_EQ(read_integers(f.id(), "/answer/level"), (std::vector<long long>{0, 0, 1, 2}));
  const testing::RawDataset chain = read_raw(f.id(), "/answer/chain");
  EXPECT_EQ(chain.type_size, 8u);
  EXPECT_EQ(read_integers(f.id(), "/answer/chain"), (std::vector<long long>{0, 1, 1LL << 40}));

  testing::Hid group(H5Oopen(f.id(), "/answer", H5P_DEFAULT), H5Oclose);
  EXPECT_EQ(read_single_string_attribute(group.get(), "description"), "what it is");
  for (const char* name : {"probability", "runs", "interval", "level", "chain", "thresholds"}) {
    testing::Hid set(H5Oopen(group.get(), name, H5P_DEFAULT), H5Oclose);
    EXPECT_TRUE(has_attribute(set.get(), "description")) << name;
    EXPECT_TRUE(has_attribute(set.get(), "units")) << name;
  }
  testing::Hid level_set(H5Oopen(group.get(), "level", H5P_DEFAULT), H5Oclose);
  EXPECT_EQ(read_single_string_attribute(level_set.get(), "units"), "1");
  testing::Hid inner(H5Oopen(group.get(), "undescribed", H5P_DEFAULT), H5Oclose);
  EXPECT_FALSE(has_attribute(inner.get(), "description"));
  EXPECT_EQ(read_double_attribute(inner.get(), "limit"), std::vector<double>{2.5});
  EXPECT_EQ(read_integer_attribute(inner.get(), "samples_per_level"), 100);
}

}  // namespace
}  // namespace treedyn
