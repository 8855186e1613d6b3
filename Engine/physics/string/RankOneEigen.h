#pragma once
// The eigenpairs of a diagonal matrix plus a symmetric rank-one update, A = D + c r r^T (c >= 0),
// in O(N^2) (Golub 1973; Bunch, Nielsen & Sorensen 1978; Gu & Eisenstat 1994; LAPACK's dlaed2,
// dlaed3, dlaed4). An eigenvalue lambda solves the secular equation
//   f(lambda) = 1 + c sum_p r_p^2 / (d_p - lambda) = 0,
// one in each interval between consecutive sorted d_p and the last in (d_max, d_max + c |r|^2); its
// eigenvector is (D - lambda I)^{-1} r. Deflation first: an entry whose weight is below rounding
// (|r_p| ~ 0, a mode with a node at the spring) keeps lambda = d_p and e_p, and of two entries with
// d_p equal within rounding a plane rotation leaves one without weight. Each remaining lambda is
// found as d_i + tau with tau relative to its nearer pole (no cancellation in d_p - lambda), and
// the eigenvectors are those of the weights recomputed from the computed eigenvalues (Loewner's
// formula), which makes them orthogonal to working precision. OFF.

#include <vector>

namespace jawari
{

struct RankOneEigen
{
    std::vector<double> eigenvalues;   // ascending
    std::vector<double> eigenvectors;  // N x N, column-major: column k the unit eigenvector of eigenvalue k,
                                       // its largest-magnitude component positive (the first of equals)
};

// d and r of one length N; c >= 0.
RankOneEigen rankOneUpdateEigen(const std::vector<double>& d, const std::vector<double>& r, double c);

}  // namespace jawari
