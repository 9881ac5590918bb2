// Argument checks shared by every algorithm of core/: each throws InvalidInput naming the
// argument and the first offending index.
#pragma once

#include <Eigen/Core>
#include <string_view>

namespace tofcomp::core {

// Every entry finite (no NaN, no Inf). Vectors are named name[k], matrices name(r, c).
void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, std::string_view name);
void require_finite(double value, std::string_view name);

// Two sequences of one length.
void require_same_length(Eigen::Index a, std::string_view name_a, Eigen::Index b,
                         std::string_view name_b);

// A strictly positive, finite scalar.
void require_positive(double value, std::string_view name);

}  // namespace tofcomp::core
