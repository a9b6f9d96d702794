// Internal: the one check of an argument's shape in the epuck room, naming the argument.
#pragma once

#include <stdexcept>
#include <string>

#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

// Throws std::invalid_argument "<name> must have shape (rows, cols)" unless it has.
inline void check_shape(const Eigen::Ref<const RowMatrixXd>& values, Eigen::Index rows,
                        Eigen::Index cols, const char* name) {
  if (values.rows() != rows || values.cols() != cols) {
    throw std::invalid_argument(std::string(name) + " must have shape (" + std::to_string(rows) +
                                ", " + std::to_string(cols) + "), not (" +
                                std::to_string(values.rows()) + ", " +
                                std::to_string(values.cols()) + ")");
  }
}

// The same for a column (N,).
inline void check_length(Eigen::Index size, Eigen::Index expected, const char* name) {
  if (size != expected) {
    throw std::invalid_argument(std::string(name) + " must have shape (" +
                                std::to_string(expected) + ",), not (" + std::to_string(size) +
                                ",)");
  }
}

}  // namespace evc
