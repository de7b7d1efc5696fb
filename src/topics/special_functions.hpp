#pragma once
// The digamma family in double precision, written out here (topics does not use Boost.Math; the
// tests compare these with boost::math::digamma/trigamma). Each shifts x up by the recurrence
// psi(x) = psi(x + 1) - 1/x (psi'(x) = psi'(x + 1) + 1/x^2) until x >= 10, then sums the
// asymptotic series; the error is below 1e-15 relative away from the root of psi near 1.46.

namespace proprio::topics::detail {

/// psi(x) = d/dx log Gamma(x), x > 0.
double digamma(double x);

/// psi'(x) = d^2/dx^2 log Gamma(x), x > 0.
double trigamma(double x);

/// The x > 0 with psi(x) = y, for any finite y: Minka (2003), Appendix C. Starts from
/// exp(y) + 1/2 (y >= -2.22) or -1/(y - psi(1)) and takes Newton steps until the relative change
/// is below 1e-15 (at most 8 steps; five give 14 digits).
double inverse_digamma(double y);

}  // namespace proprio::topics::detail
