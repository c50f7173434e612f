// Checks on single pieces of a description; each throws ModelError whose
// message starts with `who` (e.g. "body 'arm'").
#pragma once

#include <string>

#include "common/linalg.hpp"

namespace treedyn {

void require_finite(const std::string& who, const std::string& field, const Vec3& v);
void require_positive_mass(const std::string& who, double mass);
// A positive, finite value of `field` (e.g. "length", unit "m").
void require_positive(const std::string& who, const std::string& field, const std::string& unit, double value);
// Symmetric (to 1e-9 relative), positive definite, principal moments obeying
// the triangle inequality A + B >= C (to 1e-9 relative).
void require_valid_inertia(const std::string& who, const Mat3& inertia);
// Symmetric positive semi-definite (a stiffness or damping matrix).
void require_psd(const std::string& who, const std::string& field, const Mat3& m);

}  // namespace treedyn
