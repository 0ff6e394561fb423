// Small dense linear algebra for the few global unknowns of a solve.
#pragma once

#include <vector>

namespace nct::solver
{

/// x = S^-1 r for a small dense S (n x n, row-major), by Gaussian
/// elimination with partial pivoting; NaN if S is singular.
std::vector<double> solve_dense(std::vector<double> S, std::vector<double> r);

} // namespace nct::solver
