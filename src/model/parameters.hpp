// The named physical parameters of a model: one flat vector of doubles, each
// entry belonging to a named parameter (a scalar, a 3-vector or a 3x3 matrix)
// with a unit and a note saying where it enters. The names are the ones users
// write as perturbation targets (`body.rod.mass`, `gravity.z`,
// `base.z[1].frequency`, `joint.lower.stiffness`), so a target is resolved to
// vector indices once, by name, and a sample is just another vector.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace treedyn {

enum class ParameterShape {
  scalar,   // 1 entry: target NAME
  vector3,  // 3 entries x, y, z: targets NAME.x, NAME.y, NAME.z
  matrix3,  // 9 entries, row-major: target NAME (the whole matrix)
  list,     // any number of entries, each its own input: target NAME (all of them, one
            // input each), entry NAME[K] with K from 1 (a sea state's phases)
};

// The values the model accepts (derive_model refuses the others): for each
// entry of a scalar or a vector, or for each eigenvalue of a matrix.
struct ValidRange {
  double low = -std::numeric_limits<double>::infinity();
  bool low_open = false;  // low itself is refused (a mass of 0)
  static ValidRange any() { return {}; }
  static ValidRange positive() { return {0.0, true}; }
  static ValidRange non_negative() { return {0.0, false}; }
  bool bounded() const { return low > -std::numeric_limits<double>::infinity(); }
  std::string describe(const std::string& unit) const;  // "> 0 kg", ">= 0 Hz"
};

struct Parameter {
  std::string name;    // e.g. "body.rod.mass"
  std::string unit;    // SI: "kg", "m", "rad", "N m/rad", "1", ...
  std::string enters;  // where it enters the model, for people
  ParameterShape shape = ParameterShape::scalar;
  int offset = 0;    // first entry in the vector
  ValidRange valid;  // of each entry (matrices: of each eigenvalue)
  int length = 0;    // entries of a list
  int size() const;
};

class ParameterTable {
 public:
  // Appends a parameter with its nominal entries (1, 3 or 9, as the shape
  // says; a list takes as many as it is given); returns its offset. Names
  // must be unique.
  int add(std::string name, std::string unit, ParameterShape shape, std::string enters, std::span<const double> nominal,
          ValidRange valid = ValidRange::any());

  const std::vector<Parameter>& parameters() const { return parameters_; }
  const Parameter* find(std::string_view name) const;
  // The nominal vector (the job as written).
  std::span<const double> nominal() const { return nominal_; }
  std::size_t size() const { return nominal_.size(); }
  // Replaces the nominal vector (same size): a job whose [sample] section
  // makes one ensemble sample its nominal.
  void set_nominal(std::span<const double> values);
  // The parameter that holds entry `index`.
  const Parameter& owner(int index) const;
  // "gravity.z", "body.rod.mass", "joint.lower.stiffness.xy": one entry's name.
  std::string entry_name(int index) const;

 private:
  std::vector<Parameter> parameters_;
  std::unordered_map<std::string, std::size_t> by_name_;  // index in parameters_
  std::vector<double> nominal_;
};

// Component labels of the shapes: "x", "y", "z" and "xx", "xy", ... "zz"
// ("" for a scalar or a list, whose entries are NAME[K]).
std::string_view component_name(ParameterShape shape, int component);

}  // namespace treedyn
